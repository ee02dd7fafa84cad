"""What a solve would refuse in a loaded problem, found without solving,
so that ``--info`` says so instead of exiting 0: a K that is not positive
definite (a floating body; :meth:`ContactProblem.check_stiffness`) and an
obstacle whose gaps cannot be found at the contact nodes (the gap search
of the solve's gap mode at every contact node with a free DOF). A
discrete problem carries its gaps and a two-body problem's are the
mortar's: for both only K is checked."""

import numpy as np

from ..errors import SolverError
from .rigid import check_rigid_load

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
                check_rigid_load(problem, _normal_rows(problem, gaps[1]))
        except SolverError as exc:
            found.append(_one_line(exc))
    return found


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
