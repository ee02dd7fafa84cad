"""Test helper: two-body plane-strain problems in the format-v4 layout
(contract 19), assembled without SfePy and without the solver.

The P1 triangle stiffness and the structured rectangles are those of
:mod:`tet_elasticity` (∫ Bᵀ D B on each triangle, vectorised); here two
rectangles are stacked, each with its own mesh (non-matching at the
interface), K block-diagonal, and the interface segments oriented with
their body on the left (outward normal (t_y, −t_x)/|t|).
"""

import numpy as np
import scipy.sparse as sp

from tet_elasticity import mesh_problem, rectangle, stiffness


def stacked_blocks(n_upper=(3, 2), n_lower=(5, 2), width=1.0,
                   heights=(1.0, 1.0), materials=((1.0, 0.3), (1.0, 0.3)),
                   squeeze=1e-3, slave="upper", fix_x=True, curvature=0.0,
                   shift=None):
    """Block 0 = upper on [0, W]×[h₁, h₁ + h₀], block 1 = lower on
    [0, W]×[0, h₁]; ``n_*`` cells (nx, ny); ``materials`` (E, ν) per body.
    Bottom: u_y = 0, bottom-left corner also u_x = 0; top: u_y = −squeeze,
    top-left corner u_x = 0 (``fix_x``): each body's K is non-singular and
    the exact solution is uniform (σ_xx = 0, frictionless interface).
    ``slave`` = "upper" or "lower". ``curvature`` c lifts the upper
    block's bottom to y = h₁ + c (x − W/2)² (the top stays flat; contact
    then starts at the middle). ``shift``: every top node also gets
    u_x = shift (the bottom is clamped): a two-stage load path, squeeze
    then shift, for friction. Returns (problem, full K, prescribed).
    """
    h0, h1 = heights
    up, up_cells = rectangle(n_upper, (width, h0))
    up[:, 1] += curvature * (up[:, 0] - width / 2) ** 2 * (1 - up[:, 1] / h0)
    up = up + [0.0, h1]
    lo, lo_cells = rectangle(n_lower, (width, h1))
    nodes = np.concatenate([up, lo])
    offset = len(up)
    cells = np.concatenate([up_cells, lo_cells + offset])
    body = np.r_[np.zeros(len(up), np.int64), np.ones(len(lo), np.int64)]
    K = sp.block_diag([stiffness(up, up_cells, *materials[0]),
                       stiffness(lo, lo_cells, *materials[1])]).tocsr()
    prescribed = np.full(nodes.shape, np.nan)
    top, bottom = np.isclose(nodes[:, 1], h0 + h1), np.isclose(nodes[:, 1], 0)
    prescribed[top, 1], prescribed[bottom, 1] = -squeeze, 0.0
    if fix_x:
        prescribed[top & np.isclose(nodes[:, 0], 0), 0] = 0.0
        prescribed[bottom & np.isclose(nodes[:, 0], 0), 0] = 0.0
    # interface edges: upper's bottom left → right (body above = left),
    # lower's top right → left (body below = left)
    if shift is not None:
        prescribed[top, 0], prescribed[bottom, 0] = shift, 0.0
    ub = np.flatnonzero(np.isclose(up[:, 1] - curvature * (
        up[:, 0] - width / 2) ** 2, h1))
    ub = ub[np.argsort(up[ub, 0])]
    lt = np.flatnonzero(np.isclose(lo[:, 1], h1)) + offset
    lt = lt[np.argsort(-nodes[lt, 0])]
    up_segments = np.c_[ub[:-1], ub[1:]]
    lo_segments = np.c_[lt[:-1], lt[1:]]
    slave_seg, master_seg = (up_segments, lo_segments) if slave == "upper" \
        else (lo_segments, up_segments)
    contact_nodes = np.r_[slave_seg[:, 0], slave_seg[-1, 1]]
    problem = mesh_problem(nodes, cells, K, prescribed, contact_nodes,
                           slave_seg)
    attach_interface(problem, body, slave_seg, master_seg,
                     [{"name": "upper", "E": materials[0][0],
                       "nu": materials[0][1]},
                      {"name": "lower", "E": materials[1][0],
                       "nu": materials[1][1]}],
                     0 if slave == "upper" else 1)
    if shift is not None:
        _squeeze_then_shift(problem, K, prescribed)
    return problem, K, prescribed


def _squeeze_then_shift(problem, K, prescribed):
    """Load path: stage 1 the squeeze alone, stage 2 squeeze and shift."""
    first = prescribed.copy()
    first[np.isclose(problem.nodes[:, 1], problem.nodes[:, 1].max()), 0] = 0
    stages = [np.nan_to_num(first), np.nan_to_num(prescribed)]
    free = np.isnan(prescribed).ravel()
    loads = [-(sp.csr_matrix(K)[free] @ u.ravel()) for u in stages]
    problem.load_path = np.array(loads)
    problem.load_path_prescribed = np.array(stages)
    problem.load_path_steps = np.array([4, 8], np.int64)
    problem.load_path_friction = np.ones(2)


def attach_interface(problem, body, slave, master, bodies, slave_body):
    """The format-v4 fields of contract 19 on ``problem``."""
    problem.body = np.asarray(body, np.int64)
    problem.mortar_slave = np.asarray(slave, np.int64)
    problem.mortar_master = np.asarray(master, np.int64)
    problem.mortar_slave_pair = np.zeros(len(slave), np.int64)
    problem.mortar_master_pair = np.zeros(len(master), np.int64)
    problem.meta = dict(problem.meta, bodies=bodies, slave_body=slave_body,
                        master_body=1 - slave_body)
    return problem


def uniform_pressure(heights, materials, squeeze):
    """The closed form: two plane-strain layers in series under a total
    shortening δ with σ_xx = 0: σ_yy = −δ / Σ h_b (1 − ν_b²)/E_b."""
    compliance = sum(h * (1 - nu ** 2) / E
                     for h, (E, nu) in zip(heights, materials))
    return squeeze / compliance


def top_reaction(K, problem, u_reduced, prescribed):
    """Σ of the y reactions K u at the top nodes (the applied force)."""
    full = problem.full_displacement(u_reduced).ravel()
    r = (K @ full).reshape(-1, 2)
    top = np.isclose(problem.nodes[:, 1], problem.nodes[:, 1].max())
    return r[top, 1].sum()
