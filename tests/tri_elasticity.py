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
                   shift=None, side_rollers=False):
    """Block 0 = upper on [0, W]×[h₁, h₁ + h₀], block 1 = lower on
    [0, W]×[0, h₁]; ``n_*`` cells (nx, ny); ``materials`` (E, ν) per body.
    Bottom: u_y = 0, bottom-left corner also u_x = 0; top: u_y = −squeeze,
    top-left corner u_x = 0 (``fix_x``): each body's K is non-singular and
    the exact solution is uniform (σ_xx = 0, frictionless interface).
    ``slave`` = "upper" or "lower". ``curvature`` c lifts the upper
    block's bottom to y = h₁ + c (x − W/2)² (the top stays flat; contact
    then starts at the middle). ``shift``: every top node also gets
    u_x = shift (the bottom is clamped): a two-stage load path, squeeze
    then shift, for friction. ``side_rollers``: u_x = 0 on the left side
    x = 0 of both blocks (the interface's end nodes there are rollers).
    Returns (problem, full K, prescribed).
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
    if side_rollers:
        prescribed[np.isclose(nodes[:, 0], 0), 0] = 0.0
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
                        master_body=1 - slave_body,
                        E=bodies[slave_body]["E"],
                        nu=bodies[slave_body]["nu"], plane="strain",
                        load="prescribed displacement",
                        mesh="tests/tri_elasticity.py")
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


def _size(d, h0, core, ratio):
    """Mesh size at distance d from the pole: h0 within ``core``, then
    growing linearly (ratio)."""
    return h0 + ratio * np.maximum(d - core, 0.0)


def graded_half_disk(R, h0, core, ratio=0.15, upper=False):
    """Delaunay triangles of the lower (or ``upper``) half of the disk of
    radius R centred at the origin, graded from its pole (0, ∓R): size h0
    within ``core`` of the pole, growing by ``ratio`` × distance beyond.
    Points: rings around the pole inside the disk, the arc and the flat
    edge at their local size (the domain is convex, so Delaunay meshes it).
    Returns (nodes, triangles ccw, arc node ids, flat edge node ids)."""
    from scipy.spatial import Delaunay

    sign = 1.0 if upper else -1.0
    pole = np.array([0.0, sign * R])
    rings, r = [], h0
    while r < 2.2 * R:
        h = _size(r, h0, core, ratio)
        n = int(np.ceil(2 * np.pi * r / h))
        t = 2 * np.pi * (np.arange(n) + 0.5 * (len(rings) % 2)) / n
        p = pole + r * np.c_[np.cos(t), np.sin(t)]
        inside = (np.hypot(*p.T) < R - 0.5 * h) & (sign * p[:, 1] > 0.5 * h)
        rings.append(p[inside])
        r += h
    arc, s = [0.0], 0.0                       # arc length from the pole
    while s < R * np.pi / 2:
        s += _size(s, h0, core, ratio)
        arc.append(min(s, R * np.pi / 2))
    phi = np.array(arc) / R
    phi = np.r_[-phi[::-1], phi[1:]]          # angle from the pole
    arc_points = np.c_[R * np.sin(phi), sign * R * np.cos(phi)]
    x, flat = [0.0], 0.0
    while flat < R:
        flat += _size(np.hypot(flat, R), h0, core, ratio)
        x.append(min(flat, R))
    x = np.array(x)
    x = np.r_[-x[::-1], x[1:]][1:-1]          # corners are on the arc
    flat_points = np.c_[x, 0 * x]
    nodes = np.concatenate([arc_points, flat_points] + rings)
    tri = Delaunay(nodes).simplices
    X = nodes[tri]
    area = _cross2(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    tri[area < 0] = tri[area < 0][:, [0, 2, 1]]
    tri = tri[np.abs(area) > 1e-14 * R * R]
    arc_ids = np.arange(len(arc_points))
    flat_ids = np.r_[0, len(arc_points) - 1,
                     len(arc_points) + np.arange(len(flat_points))]
    return nodes, tri, arc_ids, flat_ids


def _cross2(a, b):
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def two_cylinders(R=(1.0, 1.5), materials=((1.0, 0.3), (2.0, 0.25)),
                  h0=0.002, core=0.08, squeeze=0.01, window=(0.12, 0.2),
                  shift=None, ratio=0.15, force=None, roller=False):
    """Hertz's two cylinders as two half-disks touching at the origin:
    body 0 (slave) the lower half of the disk of radius R₀ centred at
    (0, R₀), body 1 (master) the upper half of the disk of radius R₁
    centred at (0, −R₁). Flat edges: body 1's clamped, body 0's u_y =
    −squeeze, u_x = 0 (or, with ``shift``, a load path: squeeze, then
    u_x = shift). ``force`` P: body 0's flat edge free (the body held by
    the contact only, three rigid modes) and pressed down by the uniform
    traction P/(2R₀); ``roller``: body 1's flat edge held in y only (its
    x translation free too). Interface: arc segments with |x| ≤ window
    (slave, master). Returns (problem, full K, prescribed)."""
    parts, offset = [], 0
    for b, (radius, upper) in enumerate(zip(R, (False, True))):
        nodes, tri, arc, flat = graded_half_disk(radius, h0, core, ratio,
                                                 upper)
        nodes = nodes + [0.0, radius if b == 0 else -radius]
        parts.append((nodes, tri, arc + offset, flat + offset, offset))
        offset += len(nodes)
    nodes = np.concatenate([p[0] for p in parts])
    cells = np.concatenate([p[1] + p[4] for p in parts])
    body = np.repeat([0, 1], [len(parts[0][0]), len(parts[1][0])])
    K = sp.block_diag([stiffness(p[0], p[1], *materials[b])
                       for b, p in enumerate(parts)]).tocsr()
    prescribed = np.full(nodes.shape, np.nan)
    if force is None:
        prescribed[parts[0][3]] = [0.0 if shift is None else shift,
                                   -squeeze]
    prescribed[parts[1][3]] = [np.nan if roller else 0.0, 0.0]
    segments = []
    for b, half in ((0, window[0]), (1, window[1])):
        ids = parts[b][2]
        ids = ids[np.abs(nodes[ids, 0]) <= half]
        ids = ids[np.argsort(nodes[ids, 0] * (1 if b == 0 else -1))]
        segments.append(np.c_[ids[:-1], ids[1:]])
    contact_nodes = np.r_[segments[0][:, 0], segments[0][-1, 1]]
    problem = mesh_problem(nodes, cells, K, prescribed, contact_nodes,
                           segments[0])
    attach_interface(problem, body, segments[0], segments[1],
                     [{"name": "upper", "E": materials[0][0],
                       "nu": materials[0][1]},
                      {"name": "lower", "E": materials[1][0],
                       "nu": materials[1][1]}], 0)
    if shift is not None:
        _squeeze_then_shift(problem, K, prescribed)
    if force is not None:  # lumped: half of each flat segment per end
        top = parts[0][3][np.argsort(nodes[parts[0][3], 0])]
        share = np.zeros(len(top))
        share[:-1] += 0.5 * np.diff(nodes[top, 0])
        share[1:] += 0.5 * np.diff(nodes[top, 0])
        F = np.zeros(nodes.shape)
        F[top, 1] = -force * share / share.sum()
        problem.f = problem.f + F[problem.dof_map[:, 0],
                                  problem.dof_map[:, 1]]
    return problem, K, prescribed


def hertz_cylinders(P, R, materials):
    """Hertz (plane strain, per unit length): a = 2√(P R*/(π E*)),
    p₀ = 2P/(πa), 1/R* = Σ 1/R_b, 1/E* = Σ (1 − ν_b²)/E_b."""
    Rs = 1 / sum(1 / r for r in R)
    Es = 1 / sum((1 - nu ** 2) / E for E, nu in materials)
    a = 2 * np.sqrt(P * Rs / (np.pi * Es))
    return a, 2 * P / (np.pi * a)


#: The thesis's block (§4): E, ν, the force at the top-left corner, the
#: parabola x = 5.05 + 0.005 t², y = t.
BLOCK = dict(E=2e5, nu=0.3, F=(4000.0, 0.0))


def thesis_block(mesh="block_454.mesh"):
    """The thesis's block as a rigid-obstacle problem (bottom clamped, F at
    (−5, 10), Γc the edge x = 5 upwards), assembled here. Returns
    (problem, full K)."""
    import meshio

    from conftest import MESHES
    from solver.geometry.curves.parametric import ParametricCurve

    m = meshio.read(MESHES / mesh)
    nodes = np.asarray(m.points[:, :2], float)
    cells = np.asarray(m.cells_dict["triangle"], np.int64)
    X = nodes[cells]
    flip = _cross2(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]) < 0
    cells[flip] = cells[flip][:, [0, 2, 1]]
    K = stiffness(nodes, cells, BLOCK["E"], BLOCK["nu"])
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[np.isclose(nodes[:, 1], -10)] = 0.0
    edge = np.flatnonzero(np.isclose(nodes[:, 0], 5))
    edge = edge[np.argsort(nodes[edge, 1])]
    problem = mesh_problem(nodes, cells, K, prescribed, edge,
                           np.c_[edge[:-1], edge[1:]])
    corner = np.flatnonzero(np.isclose(nodes, [-5, 10]).all(axis=1))[0]
    free = np.isnan(prescribed).ravel()
    full = np.zeros(nodes.size)
    full[2 * corner:2 * corner + 2] = BLOCK["F"]
    problem.f = problem.f + full[free]
    problem.obstacle = ParametricCurve("5.05 + 0.005*t**2", "t")
    return problem, K


def block_on_parabola_body(stiffness_ratio, n_y=220, n_x=12, extent=11.0,
                           right=8.0, mesh="block_454.mesh", rigid=False):
    """The thesis block (slave) against an elastic body filling
    x ∈ [5.05 + 0.005 y², ``right``], |y| ≤ ``extent`` (master; E =
    ``stiffness_ratio`` × the block's, same ν; its edge x = right
    clamped; ``rigid``: every node of it), meshed by a mapped n_x × n_y
    grid. Returns the problem."""
    block, _ = thesis_block(mesh)
    grid, tri = rectangle((n_x, n_y), (1.0, 2 * extent))
    y = grid[:, 1] - extent
    xp = 5.05 + 0.005 * y ** 2
    obstacle = np.c_[xp + (right - xp) * grid[:, 0], y]
    n0 = len(block.nodes)
    nodes = np.concatenate([block.nodes, obstacle])
    cells = np.concatenate([block.cells, tri + n0])
    K = sp.block_diag([
        stiffness(block.nodes, block.cells, BLOCK["E"], BLOCK["nu"]),
        stiffness(obstacle, tri, stiffness_ratio * BLOCK["E"],
                  BLOCK["nu"])]).tocsr()
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[:n0][np.isclose(block.nodes[:, 1], -10)] = 0.0
    prescribed[n0 + np.flatnonzero(np.isclose(grid[:, 0], 1.0) | rigid)] = 0
    left = n0 + np.flatnonzero(np.isclose(grid[:, 0], 0.0))
    left = left[np.argsort(-nodes[left, 1])]          # downwards: body right
    slave = np.c_[block.contact_nodes[:-1], block.contact_nodes[1:]]
    problem = mesh_problem(nodes, cells, K, prescribed, block.contact_nodes,
                           slave)
    corner = np.flatnonzero(np.isclose(nodes, [-5, 10]).all(axis=1))[0]
    free = np.isnan(prescribed).ravel()
    full = np.zeros(nodes.size)
    full[2 * corner:2 * corner + 2] = BLOCK["F"]
    problem.f = problem.f + full[free]
    body = np.r_[np.zeros(n0, np.int64), np.ones(len(obstacle), np.int64)]
    return attach_interface(
        problem, body, slave, np.c_[left[:-1], left[1:]],
        [{"name": "block", **{k: BLOCK[k] for k in ("E", "nu")}},
         {"name": "parabola", "E": stiffness_ratio * BLOCK["E"],
          "nu": BLOCK["nu"]}], 0)


def floor_block(load=(0.0, -1.0), n=(8, 4), floor=0.0, E_=100.0, where="all"):
    """A 2 × 1 block of P1 triangles (tet_elasticity) on the rigid line
    y = ``floor``, no Dirichlet condition: ``load`` on every node
    ("all", lumped by nodal area) or at the top-left corner."""
    from solver.geometry.curves.parametric import ParametricCurve

    nodes, cells = rectangle(n, (2.0, 1.0))
    bottom = np.flatnonzero(nodes[:, 1] == 0.0)
    bottom = bottom[np.argsort(nodes[bottom, 0])]
    faces = np.stack([bottom[:-1], bottom[1:]], 1)
    problem = mesh_problem(nodes, cells, stiffness(nodes, cells, E_, 0.3),
                           np.full(nodes.shape, np.nan), bottom, faces)
    if where == "all":  # lumped: each triangle's area in thirds
        a = nodes[cells]
        area = 0.5 * np.abs(np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]))
        share = np.bincount(cells.ravel(), np.repeat(area / 3, 3),
                            len(nodes))
    else:
        share = np.zeros(len(nodes))
        share[np.argmin(nodes[:, 0] - nodes[:, 1])] = 1.0
    f = (share[:, None] * np.asarray(load, float)).ravel()
    problem.f = f[2 * problem.dof_map[:, 0] + problem.dof_map[:, 1]]
    problem.obstacle = ParametricCurve("t", repr(float(floor)))
    problem.meta = {"E": E_, "nu": 0.3, "plane": "strain",
                    "mesh": "2 x 1 block, P1 triangles",
                    "load": f"{tuple(load)} {where}"}
    return problem


def two_floor_blocks():
    """Two separate :func:`floor_block` s in one body, side by side on the
    floor (the second 1 to the right of the first): K has six zero
    pivots, the whole body three rigid motions, so K with three DOFs held
    is still singular (a kernel beyond the rigid-body modes)."""
    import dataclasses

    one = floor_block()
    n = len(one.nodes)
    return dataclasses.replace(
        one, K=sp.block_diag([one.K, one.K]).tocsr(),
        f=np.concatenate([one.f, one.f]),
        nodes=np.concatenate([one.nodes, one.nodes + [3.0, 0.0]]),
        cells=np.concatenate([one.cells, one.cells + n]),
        dof_map=np.concatenate([one.dof_map, one.dof_map + [n, 0]]),
        u_prescribed=np.zeros((2 * n, 2)))


def floor_block_beyond_lagged():
    """The floor block under a load path: (0, −0.5) frictionless in one
    step, then (0.4, −1) in two steps with friction. With f_c = 0.5, step 3
    needs 0.8 of friction while the lagged bound from step 2's pressure
    allows 0.75: no answer under the lagged bound, one under the implicit
    one."""
    import dataclasses

    problem = floor_block(load=(0.4, -1.0))
    first = floor_block(load=(0.0, -0.5)).f
    return dataclasses.replace(
        problem, load_path=np.stack([first, problem.f]),
        load_path_steps=np.array([1, 2]),
        load_path_friction=np.array([0.0, 1.0]))
