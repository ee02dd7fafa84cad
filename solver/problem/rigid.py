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
names it and the load's component along it.

With Coulomb friction f_c the contact forces at node i lie in the cone
|t_i| ≤ f_c λ_i, and Rᵀf must lie in the cone spanned by its generators
N_i ± f_c T_i (2D; T the modes' tangential displacements) or
N_i + f_c(cos θ T_i1 + sin θ T_i2) (3D, the disc by a circumscribed
octagon: only a load outside that larger cone is refused, certainly
unheld): :func:`check_rigid_friction`, the same decomposition on those
generators. Under the lagged bound of a load step (the thesis's Coulomb
as a sequence of Tresca problems) the tangential forces are bounded by
numbers, |t_i| ≤ b_i (3D: each component, again a superset): a bounded
least-squares problem, :func:`step_unheld`."""

import numpy as np
import scipy.optimize as opt

from ..errors import ProblemError

__all__ = ["LOAD_RTOL", "WEAK_RTOL", "check_rigid_load",
           "check_rigid_friction", "least_friction", "step_unheld",
           "mode_text", "rigid_motion", "weakly_held"]

#: A load component along an unresisted motion above this × ‖f‖₂ (and the
#: load's work relative to |Rᵀf|) is refused.
LOAD_RTOL = 1e-9

#: A rigid motion whose contact nodes move along their normals by at most
#: this fraction of their motion (:func:`weakly_held`) is held weakly.
#: Between the two kinds: a rotation held by the lever arm of the contact
#: zone has a ratio of order (zone's width)/(distance to its centre), one
#: that only the facets of a round surface see, of order h/R
#: (docs/own-problem.md has the measured values).
WEAK_RTOL = 1e-2

#: Ratios at or below this are round-off: the motion is not seen at all
#: and is handled as unresisted (:func:`solver.contact.strategies.
#: floating.unresisted`), not reported as weak.
UNSEEN_RTOL = 1e-10


def check_rigid_load(problem, N, f=None,
                     why="frictionless contact can only push"):
    """Raise :class:`ProblemError` if the load of a floating ``problem``
    (or ``f``) has a component along a rigid-body motion that no contact
    resists, N (Nc, r) the modes' normal displacements at the contact
    nodes (the module docstring), or if it presses the body onto
    nothing; ``why`` says in the message why contact does not resist."""
    _check_cone(problem, N, N, f, (
        f"no contact resists ({why}): the body would move away without "
        "bound; support it, or load it towards the obstacle"))


def check_rigid_friction(problem, N, T, friction, f=None):
    """Raise :class:`ProblemError` if no contact forces within the Coulomb
    cones of coefficient ``friction`` balance the load of a floating
    ``problem`` (or ``f``): N (Nc, r) and T (Nc, d − 1, r) the modes'
    normal and tangential displacements at the contact nodes (module
    docstring). f_c = 0 is :func:`check_rigid_load`."""
    if friction <= 0.0:
        return check_rigid_load(problem, N, f)
    _check_cone(problem, N, _cone_generators(N, T, friction), f, (
        f"contact with friction f_c = {friction:g} cannot resist (its "
        "tangential share exceeds f_c times its normal share): the body "
        "would slide away without bound; support it, or press it harder "
        "onto the obstacle"))


def _check_cone(problem, N, G, f, unheld):
    """Raise :class:`ProblemError` if the load f (default the problem's)
    presses the body onto nothing (no resultant along the modes, or no
    contact normal N sees them), or if Rᵀf is not in the cone of the
    rows of G: "... along the rigid-body motion d that ``unheld``"."""
    R, _ = problem.rigid_modes()
    if R.shape[1] == 0:
        return
    f = problem.f if f is None else np.asarray(f, float)
    e = R.T @ f
    size = LOAD_RTOL * max(float(np.linalg.norm(f)), 1e-300)
    if np.linalg.norm(e) <= size or np.abs(N).max(initial=0.0) == 0.0:
        raise ProblemError(
            f"f: the body is held by contact only ({_modes_text(problem)}) "
            "but the load has no resultant along them: nothing presses it "
            "onto the obstacle, its position is undetermined; support it "
            "or load it towards the obstacle")
    found = _unheld_share(problem, G, f)
    if found is not None:
        component, text = found
        raise ProblemError(
            f"f: the load has a component {component:.6g} along the "
            f"rigid-body motion {text} that {unheld}")


def _unheld_share(problem, G, f):
    """None if the load f is in the cone of the rows of G (the modes'
    share of what contact forces can do), else (the load's component
    along the motion it drives, that motion in words)."""
    R, C = problem.rigid_modes()
    e = R.T @ f
    size = LOAD_RTOL * max(float(np.linalg.norm(f)), 1e-300)
    # Moreau: e = d + Gᵀμ, d the projection of e onto {d: G d ≤ 0} (the
    # motions no contact stops), Gᵀμ (μ ≥ 0, NNLS) what contact forces can
    # balance; d ≠ 0 is the load's share no contact resists, and d/|d| the
    # motion along which the load does the most work.
    scale = np.abs(G).max()
    mu, _ = opt.nnls(G.T / scale, e, maxiter=50 * max(len(G), 10))
    d = e - G.T @ mu / scale
    if float(e @ d) <= size * np.linalg.norm(e):
        return None
    motion = R @ d
    peak = _peak(problem, motion)
    return float(f @ motion) / peak, mode_text(problem, C @ d / peak)


def least_friction(problem, N, T, f=None, largest=1e3):
    """The least Coulomb coefficient f_c whose cones at the contact nodes
    hold the load f (default the problem's) of a floating ``problem`` —
    0 if frictionless contact does, None if no f_c ≤ ``largest`` does (the
    load pulls the body away). N, T as :func:`check_rigid_friction`. The
    loads held form a cone that grows with f_c, so bisection (to 1e-4
    relative) on :func:`check_rigid_friction`'s test; in 3D its cone is
    the circumscribed octagon's, so the f_c found may be up to
    1 − cos(π/8) ≈ 8 % below the true one."""
    f = problem.f if f is None else np.asarray(f, float)
    if _unheld_share(problem, N, f) is None:
        return 0.0

    def held(friction):
        return _unheld_share(problem, _cone_generators(N, T, friction),
                             f) is None

    if not held(largest):
        return None
    low, high = 0.0, largest
    while high - low > 1e-4 * high:
        middle = 0.5 * (low + high) if low else high / 16
        if held(middle):
            high = middle
        else:
            low = middle
    return high


def _cone_generators(N, T, friction):
    """The rows N_i ± f_c T_i (2D) or N_i + f_c/cos(π/8)(cos θ T_i1 +
    sin θ T_i2), θ = kπ/4 (3D): generators of (a cone containing) the
    modes' share of the Coulomb cones."""
    T = np.asarray(T, float).reshape(len(N), -1, N.shape[1])
    if T.shape[1] == 1:
        return np.concatenate([N + friction * T[:, 0],
                               N - friction * T[:, 0]])
    angles = np.arange(8) * np.pi / 4
    wide = friction / np.cos(np.pi / 8)
    return np.concatenate([N + wide * (np.cos(a) * T[:, 0]
                                       + np.sin(a) * T[:, 1])
                           for a in angles])


def step_unheld(problem, N, T, f, bounds):
    """None, or the rigid motion (its coefficients on the translations
    and rotations, scaled to a peak displacement 1) and the load's
    component along it, if no normal forces λ ≥ 0 with tangential forces
    |t_i| ≤ ``bounds``_i (each component in 3D) balance the load ``f`` of
    a floating ``problem`` (module docstring: the lagged bound)."""
    R, C = problem.rigid_modes()
    e = R.T @ np.asarray(f, float)
    norm = float(np.linalg.norm(e))
    if R.shape[1] == 0 or norm == 0.0:
        return None
    T = np.asarray(T, float).reshape(len(N), -1, N.shape[1])
    k = T.shape[1]
    scale = max(np.abs(N).max(initial=0.0), np.abs(T).max(initial=0.0),
                1e-300)
    A = np.concatenate([N, T.transpose(1, 0, 2).reshape(-1, N.shape[1])]).T
    b = np.repeat(np.asarray(bounds, float)[None], k, axis=0).ravel()
    lower = np.concatenate([np.zeros(len(N)), -b * scale])
    upper = np.concatenate([np.full(len(N), np.inf), b * scale])
    upper = np.maximum(upper, lower)  # b = 0: the interval [0, 0]
    found = opt.lsq_linear(A / scale, e, bounds=(lower, upper + 1e-300),
                           method="bvls", tol=1e-13)
    d = e - A @ found.x / scale
    if np.linalg.norm(d) <= 1e-7 * norm:
        return None
    motion = R @ d
    peak = _peak(problem, motion)
    return C @ d / peak, float(np.asarray(f, float) @ motion) / peak


def weakly_held(problem, N, G):
    r"""The rigid motions of a floating ``problem`` that the contact
    normals see only weakly: [(text, ratio)], ``text`` the motion in words
    (:func:`mode_text`; in 2D also as a rotation about its centre),
    ``ratio`` ∈ (UNSEEN_RTOL, WEAK_RTOL] the share of the contact nodes'
    motion along their normals. N (Nc, r): the modes' normal
    displacements at the contact nodes; G (n_c, r): the modes at those
    nodes' DOFs (every component).

    The ratios are the singular values of N in the metric of G,

    .. math:: ρ_k = \min_{\dim V = k}\max_{α ∈ V}
              \frac{‖Nα‖}{‖Gα‖} ∈ [0, 1]

    (|n·u| ≤ |u| node by node): 0 for a motion along the contact surface
    (a flat sliding on a flat, handled exactly as unresisted), 1 for a
    motion along the normals, and of order h/R for a motion along a round
    surface that only its polygon's facets see (the upper of two cylinders
    spinning about the lower one's centre). Such a motion is resisted by
    round-off-sized lever arms: the answer's share along it is arbitrary
    (set by the mesh), and the Newton matrices are ill-conditioned along
    it. Independent of the body's size and of how R is scaled."""
    N, G = np.asarray(N, float), np.asarray(G, float)
    if N.shape[1] == 0 or not len(N):
        return []
    _, s, Wt = np.linalg.svd(G, full_matrices=False)
    keep = s > UNSEEN_RTOL * max(s.max(initial=0.0), 1e-300)
    W = Wt[keep].T / s[keep]  # α per unit motion of the contact nodes
    _, rho, Vt = np.linalg.svd(N @ W, full_matrices=True)
    rho = np.concatenate([rho, np.zeros(W.shape[1] - len(rho))])
    R, C = problem.rigid_modes()
    found = []
    for ratio, v in zip(rho, Vt):
        if not UNSEEN_RTOL < ratio <= WEAK_RTOL:
            continue
        alpha = W @ v
        motion = R @ alpha
        peak = _peak(problem, motion)
        c = C @ alpha / peak
        found.append((_centre_text(problem, c) or mode_text(problem, c),
                      float(ratio)))
    return found


def _centre_text(problem, c):
    """In 2D, a motion of one body with a rotation, as the rotation about
    the point it leaves in place ("rotation ω rad about (x, y)", "of body
    b: ..." for several bodies); "" otherwise."""
    mesh, _ = _mesh(problem)
    if mesh.dim != 2:
        return ""
    blocks = _blocks(mesh)
    moving = [(b, mine) for b, mine in blocks
              if np.any(np.abs(c[3 * b:3 * b + 3])
                        > 1e-9 * np.abs(c).max(initial=0.0))]
    if len(moving) != 1:
        return ""
    b, mine = moving[0]
    t, w = c[3 * b:3 * b + 2], c[3 * b + 2]
    if abs(w) <= 1e-9 * np.abs(c[3 * b:3 * b + 3]).max():
        return ""
    centre, length = _frame(mesh, mine)
    omega = w / length
    point = centre + np.array([-t[1], t[0]]) / omega
    point = np.where(np.abs(point) <= 1e-9 * length, 0.0, point)
    text = f"rotation {omega:.3g} rad about ({point[0]:.4g}, {point[1]:.4g})"
    return text if len(blocks) == 1 else f"of body {b}: {text}"


def _mesh(problem):
    """(the meshed problem, the map to its DOFs or None): a two-body
    problem's nodewise equivalent in v names its motions on the bodies'
    mesh (``original``), u = T⁻¹v (``T_inv``)."""
    original = getattr(problem, "original", None)
    if original is None:
        return problem, None
    return original, problem.T_inv


def _blocks(mesh):
    """[(body, its DOFs' mask)]: one entry per body of the mesh."""
    if mesh.n_bodies == 1:
        return [(0, np.ones(mesh.n_dofs, bool))]
    groups = mesh.body[mesh.dof_map[:, 0]]
    return [(b, groups == b) for b in range(mesh.n_bodies)]


def _frame(mesh, mine):
    """(centre, length) of the rigid motions of the DOFs ``mine``
    (:func:`solver.linalg.kernel.rigid_motions`)."""
    points = mesh.dof_points()[mine]
    centre = points.mean(axis=0)
    return centre, float(np.abs(points - centre).max(initial=0.0)) or 1.0


def _peak(problem, motion):
    """The largest nodal displacement of a reduced vector ``motion``."""
    mesh, T_inv = _mesh(problem)
    if T_inv is not None:
        motion = T_inv @ motion
    full = np.zeros((len(mesh.nodes), mesh.dim))
    full[mesh.dof_map[:, 0], mesh.dof_map[:, 1]] = motion
    return float(np.linalg.norm(full, axis=1).max(initial=0.0)) or 1.0


def rigid_motion(problem, u):
    """The rigid-body motion that best fits the displacement u (least
    squares over the DOFs, independent of the DOFs held for K⁺): a dict
    of ``alpha`` = Rᵀu, ``translation`` (of the centroid of the DOFs'
    points) and ``rotation`` (the angle in 2D, the vector in 3D), in the
    problem's units, ``modes`` (r) and ``body`` (of several bodies, the
    first one held by contact only)."""
    R, C = problem.rigid_modes()
    alpha = R.T @ np.asarray(u, float)
    mesh, _ = _mesh(problem)
    d = mesh.dim
    k = 3 if d == 2 else 6
    c = C @ alpha
    body = next((b for b, _ in _blocks(mesh)
                 if np.abs(C[b * k:(b + 1) * k]).max(initial=0.0) > 0), 0)
    _, length = _frame(mesh, _blocks(mesh)[body][1])
    c = c[body * k:(body + 1) * k]
    return dict(alpha=alpha, translation=c[:d], rotation=c[d:] / length,
                modes=int(R.shape[1]), body=int(body))


def mode_text(problem, c):
    """A rigid motion of coefficients ``c`` on the translations and
    rotations (:func:`solver.linalg.kernel.rigid_motions`; body by body
    for several bodies), in words."""
    mesh, _ = _mesh(problem)
    d = mesh.dim
    k = 3 if d == 2 else 6
    c = np.asarray(c, float)
    c = np.where(np.abs(c) <= 1e-9 * np.abs(c).max(initial=0.0), 0.0, c)
    blocks = _blocks(mesh)
    texts = []
    for b, mine in blocks:
        block = c[b * k:(b + 1) * k]
        if not np.any(block):
            continue
        text = _motion_text(block, *_frame(mesh, mine), d)
        texts.append(text if len(blocks) == 1 else f"of body {b}: {text}")
    return "; ".join(texts) or f"0 along {'xyz'[:d]}"


def _motion_text(c, centre, length, d):
    """One body's motion of coefficients ``c`` (nonzero), in words."""
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
    return " + ".join(parts)


def _modes_text(problem):
    _, C = problem.rigid_modes()
    return f"{C.shape[1]} rigid-body mode{'s' if C.shape[1] > 1 else ''} free"
