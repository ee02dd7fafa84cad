"""Test helper: two elastic boxes stacked in 3D (the contact patch test and
the block sliding on a block), assembled without SfePy
(tests/tet_elasticity.py), with their interface triangles for the dual
mortar (format version 4 in 3D)."""

import numpy as np
import scipy.sparse as sp

from tet_elasticity import box, mesh_problem, stiffness
from tri_elasticity import attach_interface as attach_2d


def plane_faces(nodes, tets, axis, value):
    """The faces of ``tets`` whose three vertices lie on the plane
    x_axis = value, oriented outwards (right-hand rule)."""
    on = np.isclose(nodes[:, axis], value)
    skip = np.array([[1, 2, 3, 0], [0, 2, 3, 1], [0, 1, 3, 2], [0, 1, 2, 3]])
    faces = tets[:, skip].reshape(-1, 4)
    faces = faces[on[faces[:, :3]].all(axis=1)]
    p = nodes[faces]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    inward = np.einsum("ij,ij->i", normal, p[:, 3] - p[:, 0]) > 0
    tri = faces[:, :3].copy()
    tri[inward] = tri[inward][:, [0, 2, 1]]
    return tri


def jitter_plane(nodes, axis, value, h, amount, seed):
    """Move the nodes on the plane x_axis = value that are inside the box's
    cross-section by up to ``amount`` × h within the plane (the interface
    mesh becomes irregular; the tetrahedra stay valid for amount < ¼)."""
    rng = np.random.default_rng(seed)
    on = np.isclose(nodes[:, axis], value)
    other = [a for a in range(3) if a != axis]
    lo, hi = nodes[:, other].min(axis=0), nodes[:, other].max(axis=0)
    inner = on & ((nodes[:, other] > lo + 1e-9)
                  & (nodes[:, other] < hi - 1e-9)).all(axis=1)
    nodes = nodes.copy()
    nodes[np.ix_(inner, other)] += rng.uniform(-amount * h, amount * h,
                                               (inner.sum(), 2))
    return nodes


def stacked_boxes(n_upper=(3, 3, 2), n_lower=(4, 4, 2), heights=(0.5, 0.5),
                  materials=((1.0, 0.3), (3.0, 0.2)), squeeze=1e-3,
                  slave="upper", jitter=0.2, shift=None, pressure=None):
    """Box 0 = upper on [0, 1]²×[h₁, h₁ + h₀], box 1 = lower on
    [0, 1]²×[0, h₁], ``n_*`` cells (nx, ny, nz) each, interface nodes
    jittered (non-matching, irregular). Press: the lower bottom u_z = 0,
    the upper top u_z = −squeeze; u_x = 0 on the edges x = 0 and u_y = 0 on
    the edges y = 0 of those two faces (off the interface): the exact
    solution is uniaxial stress σ_zz = −p, p = squeeze / Σ h_b/E_b, both
    blocks free to expand sideways. ``shift`` (sx, sy): the lower bottom
    and the upper top clamped, a load path squeeze then u = (sx, sy,
    −squeeze) at the top. ``pressure`` p: the upper top free (the upper
    box held by the contact only, six rigid modes) and pressed by p (nodal
    forces: a third of each top triangle's area); the exact solution is
    σ_zz = −p. Returns (problem, full K, prescribed)."""
    h0, h1 = heights
    up, up_cells = box(n_upper, (1.0, 1.0, h0))
    up = jitter_plane(up, 2, 0.0, 1 / max(n_upper[:2]), jitter, 1)
    up = up + [0.0, 0.0, h1]
    lo, lo_cells = box(n_lower, (1.0, 1.0, h1))
    lo = jitter_plane(lo, 2, h1, 1 / max(n_lower[:2]), jitter, 2)
    nodes = np.concatenate([up, lo])
    offset = len(up)
    cells = np.concatenate([up_cells, lo_cells + offset])
    body = np.r_[np.zeros(len(up), np.int64), np.ones(len(lo), np.int64)]
    K = sp.block_diag([stiffness(up, up_cells, *materials[0]),
                       stiffness(lo, lo_cells, *materials[1])]).tocsr()
    prescribed = np.full(nodes.shape, np.nan)
    x, y, z = nodes.T
    top, bottom = np.isclose(z, h0 + h1), np.isclose(z, 0)
    if shift is None:
        prescribed[top, 2], prescribed[bottom, 2] = -squeeze, 0.0
        for face in (top, bottom) if pressure is None else (bottom,):
            prescribed[face & np.isclose(x, 0), 0] = 0.0
            prescribed[face & np.isclose(y, 0), 1] = 0.0
    else:
        prescribed[bottom] = 0.0
        prescribed[top] = [shift[0], shift[1], -squeeze]
    upper_faces = plane_faces(nodes, cells[:len(up_cells)], 2, h1)
    lower_faces = plane_faces(nodes, cells[len(up_cells):], 2, h1)
    slave_faces, master_faces = (upper_faces, lower_faces) \
        if slave == "upper" else (lower_faces, upper_faces)
    contact_nodes = np.unique(slave_faces)
    problem = mesh_problem(nodes, cells, K, prescribed, contact_nodes,
                           slave_faces)
    bodies = [{"name": "upper box", "E": materials[0][0],
               "nu": materials[0][1]},
              {"name": "lower box", "E": materials[1][0],
               "nu": materials[1][1]}]
    attach_interface(problem, body, slave_faces, master_faces, bodies,
                     0 if slave == "upper" else 1)
    if pressure is not None:
        prescribed[top] = np.nan
        problem = mesh_problem(nodes, cells, K, prescribed, contact_nodes,
                               slave_faces)
        attach_interface(problem, body, slave_faces, master_faces, bodies,
                         0 if slave == "upper" else 1)
        faces = plane_faces(nodes, cells[:len(up_cells)], 2, h0 + h1)
        a = nodes[faces]
        area = 0.5 * np.linalg.norm(np.cross(a[:, 1] - a[:, 0],
                                             a[:, 2] - a[:, 0]), axis=1)
        F = np.zeros(nodes.shape)
        np.add.at(F[:, 2], faces.ravel(), np.repeat(-pressure * area / 3, 3))
        problem.f = F[problem.dof_map[:, 0], problem.dof_map[:, 1]]
    if shift is not None:
        first = prescribed.copy()
        first[top, :2] = 0.0
        stages = [np.nan_to_num(first), np.nan_to_num(prescribed)]
        free = np.isnan(prescribed).ravel()
        problem.load_path = np.array([-(K[free] @ u.ravel())
                                      for u in stages])
        problem.load_path_prescribed = np.array(stages)
        problem.load_path_steps = np.array([2, 4], np.int64)
        problem.load_path_friction = np.ones(2)
    return problem, K, prescribed


def attach_interface(problem, body, slave, master, bodies, slave_body):
    """The two-body fields of a 3D file on ``problem``: those of the 2D
    helper (tests/tri_elasticity.py) without ``plane``."""
    attach_2d(problem, body, slave, master, bodies, slave_body)
    problem.meta.pop("plane")
    problem.meta["mesh"] = "tests/tet_two_body.py"
    return problem


def uniaxial_pressure(heights, materials, squeeze):
    """p = δ / Σ h_b/E_b: two layers in series under uniaxial stress."""
    return squeeze / sum(h / E for h, (E, _) in zip(heights, materials))


def top_reaction(K, problem, u_reduced, axis=2):
    """Σ of the reactions K u along ``axis`` at the top nodes."""
    full = problem.full_displacement(u_reduced).ravel()
    r = (K @ full).reshape(-1, 3)
    top = np.isclose(problem.nodes[:, 2], problem.nodes[:, 2].max())
    return r[top, axis].sum()
