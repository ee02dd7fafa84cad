"""What a solve would refuse in a loaded problem, found without solving,
so that ``--info`` says so instead of exiting 0: a K that is not positive
definite (a floating body; :meth:`ContactProblem.check_stiffness`) and an
obstacle whose gaps cannot be found at the contact nodes (the gap search
of the solve's gap mode at every contact node with a free DOF). A
discrete problem carries its gaps and a two-body problem's are the
mortar's: for both only K is checked."""

import numpy as np

from ..errors import ProblemError, SolverError
from .rigid import check_rigid_load, least_friction

__all__ = ["GAP_MODES", "refusals", "checks_made"]

#: The gap modes of the solvers (thesis §2.1.1 / §2.1.2).
GAP_MODES = ("obstacle", "body")


def checks_made(problem, gap="obstacle"):
    """The names of the checks :func:`refusals` makes for ``problem``."""
    made = ["K positive definite" if problem.kind != "mesh"
            or not problem.floating else
            "K positive semidefinite, its kernel the rigid-body modes"]
    if _has_obstacle(problem):
        made.append(f"gaps from the {gap} at "
                    f"{len(_candidates(problem))} contact nodes")
    return made


def refusals(problem, gap="obstacle"):
    """The one-line reasons (each as the solve would print it after
    ``error:``) for which a solve of ``problem`` in the ``gap`` mode would
    stop before iterating; empty: it would start."""
    if gap not in GAP_MODES:
        raise SolverError(f"gap mode must be one of {GAP_MODES}, got {gap!r}")
    found = []
    try:
        problem.check_stiffness()
    except SolverError as exc:
        found.append(_one_line(exc))
    if _has_obstacle(problem):
        try:
            gaps = _gaps(problem, gap)
            if not found and problem.floating:  # can contact hold it?
                _check_floating_load(problem, gaps[1])
        except SolverError as exc:
            found.append(_one_line(exc))
    return found


def _check_floating_load(problem, normal):
    """:func:`~.rigid.check_rigid_load` at the candidates; a load that
    frictionless contact cannot hold but Coulomb friction can is refused
    with the least f_c that holds it (:func:`~.rigid.least_friction`)
    and, without a load path, the implicit bound (the lagged one gives the
    first load step no friction). The message names solve()'s options
    (``friction=F``); the command line says them as its flags."""
    N = _normal_rows(problem, normal)
    try:
        check_rigid_load(problem, N)
    except ProblemError as exc:
        message = _one_line(exc)
        if "that no contact resists" not in message:
            raise  # nothing presses the body onto the obstacle
        loads = [(problem.f, 1.0)] if problem.load_path is None else [
            (end, factor) for end, factor in zip(
                problem.load_path, problem.load_path_friction) if factor > 0]
        T = _tangential_rows(problem, normal)
        least = [least_friction(problem, N, T, f) for f, _ in loads]
        if not loads or any(value is None for value in least):
            raise
        # a stage's coefficient is f_c times its factor
        least = [value / factor for value, (_, factor) in zip(least, loads)]
        head = message.split(" that no contact resists")[0]
        bound = ("" if problem.load_path is not None else
                 " and coulomb='implicit' (the lagged bound gives the "
                 "first load step no friction)")
        raise ProblemError(
            f"{head} that frictionless contact cannot resist; it needs "
            f"friction: friction=F with F ≥ {_up(max(least))} (the least "
            f"coefficient whose Coulomb cones at the contact nodes hold "
            f"the load){bound}") from None


def _up(value):
    """``value`` rounded up to 3 significant digits, as text."""
    if value <= 0:
        return "0"
    digits = 2 - int(np.floor(np.log10(value)))
    return f"{np.ceil(value * 10 ** digits - 1e-9) / 10 ** digits:.3g}"


def _tangential_rows(problem, normal):
    """T (Nc, d − 1, r): the rigid modes' displacement along the
    tangents of each candidate's ``normal`` at its free DOFs."""
    from ..geometry.frames import tangent_basis

    R, _ = problem.rigid_modes()
    dofs = problem.contact_dofs[_candidates(problem)]
    tangents = tangent_basis(normal)
    T = np.zeros((len(dofs), tangents.shape[1], R.shape[1]))
    for k in range(dofs.shape[1]):
        free = dofs[:, k] >= 0
        T[free] += tangents[free, :, k, None] * R[dofs[free, k]][:, None]
    return T


def _normal_rows(problem, normal):
    """N (Nc, r): the rigid modes' displacement along the ``normal`` of
    each candidate (:func:`_candidates`) at its free DOFs."""
    R, _ = problem.rigid_modes()
    dofs = problem.contact_dofs[_candidates(problem)]
    N = np.zeros((len(dofs), R.shape[1]))
    for k in range(dofs.shape[1]):
        free = dofs[:, k] >= 0
        N[free] += normal[free, k, None] * R[dofs[free, k]]
    return N


def _one_line(exc):
    return " ".join(str(exc).split())


def _has_obstacle(problem):
    return problem.kind == "mesh" and problem.obstacle is not None \
        and not problem.is_mortar


def _candidates(problem):
    """Positions along Γc of the contact nodes with a free DOF."""
    return np.flatnonzero(~(problem.contact_dofs < 0).all(axis=1))


def _gaps(problem, gap):
    """The gaps and normals of the candidates (raises what the solve
    raises: GapError, GeometryError, SolverError)."""
    index = _candidates(problem)
    ids = problem.contact_nodes[index]
    points = problem.nodes[ids]
    if problem.dim == 3:
        surface = problem.obstacle
        if isinstance(surface, dict):  # a spec not yet made a surface
            from ..geometry.surfaces import surface_from_spec

            surface = surface_from_spec(surface)
        if gap == "obstacle":
            return surface.gap_along_obstacle_normal(points)
        from ..geometry.surfaces.normals import surface_normals

        normal = surface_normals(problem.nodes, problem.contact_faces,
                                 problem.contact_nodes)[index]
        return surface.gap_along_rays(points, normal)
    from ..geometry.curves import obstacle_gaps
    from ..geometry.curves.normals import boundary_normals

    body = boundary_normals(problem.nodes, problem.cells,
                            problem.contact_nodes)[index]
    return obstacle_gaps(points, problem.obstacle, body, gap, node_ids=ids)
