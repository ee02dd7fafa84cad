r"""The rigid-body motions of a body held only by contact, in words and
numbers, and the check that contact can hold its load.

A load f on a body with rigid-body modes R (:meth:`ContactProblem.
rigid_modes`) is balanced by frictionless contact forces λ ≥ 0 only if
Rᵀf = −Nᵀλ for some λ ≥ 0, N (Nc × r) the modes' normal displacements at
the contact nodes. Farkas' lemma: otherwise some rigid motion d moves no
node into the obstacle (N d ≤ 0) while the load does work along it
(Rᵀf · d > 0): the body would move away without bound, and the problem
has no solution. By Moreau's decomposition e = Rᵀf = d + Nᵀμ (μ ≥ 0 by
non-negative least squares), d is the projection of e onto those motions,
and d/|d| the one along which the load does the most work: the refusal
names it and the load's component along it."""

import numpy as np
import scipy.optimize as opt

from ..errors import ProblemError

__all__ = ["LOAD_RTOL", "check_rigid_load", "mode_text", "rigid_motion"]

#: A load component along an unresisted motion above this × ‖f‖₂ (and the
#: load's work relative to |Rᵀf|) is refused.
LOAD_RTOL = 1e-9


def check_rigid_load(problem, N):
    """Raise :class:`ProblemError` if the load of a floating ``problem``
    has a component along a rigid-body motion that no contact resists,
    N (Nc, r) the modes' normal displacements at the contact nodes (the
    module docstring), or if it presses the body onto nothing."""
    R, C = problem.rigid_modes()
    if R.shape[1] == 0:
        return
    e = R.T @ problem.f
    size = LOAD_RTOL * max(float(np.linalg.norm(problem.f)), 1e-300)
    scale = np.abs(N).max(initial=0.0)
    if np.linalg.norm(e) <= size or scale == 0.0:
        raise ProblemError(
            f"f: the body is held by contact only ({_modes_text(problem)}) "
            "but the load has no resultant along them: nothing presses it "
            "onto the obstacle, its position is undetermined; support it "
            "or load it towards the obstacle")
    # Moreau: e = d + Nᵀμ, d the projection of e onto {d: N d ≤ 0} (the
    # motions no contact stops), Nᵀμ (μ ≥ 0, NNLS) what contact forces can
    # balance; d ≠ 0 is the load's share no contact resists, and d/|d| the
    # motion along which the load does the most work.
    mu, _ = opt.nnls(N.T / scale, e, maxiter=50 * max(len(N), 10))
    d = e - N.T @ mu / scale
    if float(e @ d) > size * np.linalg.norm(e):
        motion = R @ d
        peak = _peak(problem, motion)
        component = float(problem.f @ motion) / peak
        raise ProblemError(
            f"f: the load has a component {component:.6g} along the "
            f"rigid-body motion {mode_text(problem, C @ d / peak)} that no "
            "contact resists (frictionless contact can only push): the "
            "body would move away without bound; support it, or load it "
            "towards the obstacle")


def _peak(problem, motion):
    """The largest nodal displacement of a reduced vector ``motion``."""
    full = np.zeros((len(problem.nodes), problem.dim))
    full[problem.dof_map[:, 0], problem.dof_map[:, 1]] = motion
    return float(np.linalg.norm(full, axis=1).max(initial=0.0)) or 1.0


def rigid_motion(problem, u):
    """The rigid-body motion that best fits the displacement u (least
    squares over the DOFs, independent of the DOFs held for K⁺): a dict
    of ``alpha`` = Rᵀu, ``translation`` (of the centroid of the DOFs'
    points) and ``rotation`` (the angle in 2D, the vector in 3D), in the
    problem's units, and ``modes`` (r)."""
    R, C = problem.rigid_modes()
    alpha = R.T @ np.asarray(u, float)
    points = problem.dof_points()
    length = float(np.abs(points - points.mean(axis=0)).max(initial=0.0)) \
        or 1.0
    c = C @ alpha
    d = problem.dim
    return dict(alpha=alpha, translation=c[:d], rotation=c[d:] / length,
                modes=int(R.shape[1]))


def mode_text(problem, c):
    """A rigid motion of coefficients ``c`` on the translations and
    rotations (:func:`solver.linalg.kernel.rigid_motions`), in words."""
    points = problem.dof_points()
    centre = points.mean(axis=0)
    length = float(np.abs(points - centre).max(initial=0.0)) or 1.0
    d = problem.dim
    names = "xyz"[:d]
    c = np.asarray(c, float)
    c = np.where(np.abs(c) <= 1e-9 * np.abs(c).max(initial=0.0), 0.0, c)
    parts = []
    t = c[:d]
    if np.abs(t).max() > 1e-9 * np.abs(c).max():
        parts.append("translation (" + ", ".join(f"{v:.3g}" for v in t)
                     + ")")
    w = c[d:] / length
    if np.abs(c[d:]).max() > 1e-9 * np.abs(c).max():
        at = ", ".join(f"{v:.4g}" for v in centre)
        if d == 2:
            parts.append(f"rotation {w[0]:.3g} rad about ({at})")
        else:
            parts.append("rotation (" + ", ".join(f"{v:.3g}" for v in w)
                         + f") rad about ({at})")
    return " + ".join(parts) or f"0 along {names}"


def _modes_text(problem):
    _, C = problem.rigid_modes()
    return f"{C.shape[1]} rigid-body mode{'s' if C.shape[1] > 1 else ''} free"
