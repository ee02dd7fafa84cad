"""Test helper: P1 linear elasticity assembled sparsely and vectorised, on
tetrahedra (3D) and triangles (2D plane strain), and box/slab meshes.

Independent of SfePy and of the solver: the stiffness of a P1 simplex is
∫ Bᵀ D B = vol · Bᵀ D B with B from the gradients of the barycentric
coordinates (the inverse of [1 x y (z)] at the vertices; Zienkiewicz &
Taylor, *The Finite Element Method*, vol. 1, §6). Nothing loops over
elements or nodes.
"""

import itertools

import numpy as np
import scipy.sparse as sp

from solver.problem import ContactProblem


def elasticity_matrix(E, nu, dim):
    """D (Voigt; 3D: xx yy zz yz xz xy; 2D plane strain: xx yy xy)."""
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    n = 3 if dim == 2 else 6
    D = np.zeros((n, n))
    D[:dim, :dim] = lam
    D[np.arange(dim), np.arange(dim)] += 2 * mu
    D[np.arange(dim, n), np.arange(dim, n)] = mu
    return D


def stiffness(nodes, cells, E=1.0, nu=0.3):
    """Global K (n·d × n·d, CSR; DOF d·node + component) of P1 simplices."""
    nodes, cells = np.asarray(nodes, float), np.asarray(cells, np.int64)
    d, k = nodes.shape[1], cells.shape[1]
    X = nodes[cells]                                     # (e, k, d)
    A = np.concatenate([np.ones((len(cells), k, 1)), X], axis=2)
    vol = np.abs(np.linalg.det(A)) / (1 if d == 1 else 2 if d == 2 else 6)
    G = np.linalg.inv(A)[:, 1:, :]                       # (e, d, k) ∇λ_j
    nv = 3 if d == 2 else 6
    B = np.zeros((len(cells), nv, d * k))
    for i in range(d):                                   # normal strains
        B[:, i, i::d] = G[:, i, :]
    pairs = [(0, 1)] if d == 2 else [(1, 2), (0, 2), (0, 1)]
    for r, (i, j) in enumerate(pairs):                   # shear strains
        B[:, d + r, i::d] = G[:, j, :]
        B[:, d + r, j::d] = G[:, i, :]
    Ke = vol[:, None, None] * np.einsum(
        "eai,ab,ebj->eij", B, elasticity_matrix(E, nu, d), B)
    dofs = (d * cells[:, :, None] + np.arange(d)).reshape(len(cells), -1)
    rows = np.repeat(dofs, d * k, axis=1).ravel()
    cols = np.tile(dofs, (1, d * k)).ravel()
    K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(d * len(nodes),) * 2)
    return 0.5 * (K + K.T)


def surface_mass(nodes, faces, contact_nodes):
    """P1 mass matrix of the facets ``faces`` (triangles in 3D, segments in
    2D) on ``contact_nodes`` (Nc × Nc): ∫ φ_i φ_j."""
    nodes = np.asarray(nodes, float)
    faces = np.asarray(faces, np.int64)
    k = faces.shape[1]
    X = nodes[faces]
    if k == 3:
        size = 0.5 * np.linalg.norm(np.cross(X[:, 1] - X[:, 0],
                                             X[:, 2] - X[:, 0]), axis=1)
        local = (np.ones((3, 3)) + np.eye(3)) / 12.0
    else:
        size = np.linalg.norm(X[:, 1] - X[:, 0], axis=1)
        local = (np.ones((2, 2)) + np.eye(2)) / 6.0
    position = np.full(len(nodes), -1)
    position[contact_nodes] = np.arange(len(contact_nodes))
    p = position[faces]
    rows, cols = np.repeat(p, k, axis=1).ravel(), np.tile(p, (1, k)).ravel()
    vals = (size[:, None, None] * local).ravel()
    n = len(contact_nodes)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def box(n, lengths=(1.0, 1.0, 1.0)):
    """Structured tetrahedral mesh of [0, Lx]×[0, Ly]×[0, Lz], n = (nx, ny,
    nz) cells; each hexahedron split into 6 tetrahedra along its main
    diagonal (Kuhn's conforming split). Returns (nodes, tets)."""
    nx, ny, nz = n
    axes = [np.linspace(0, L, m + 1) for L, m in zip(lengths, n)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    ids = np.arange(len(nodes)).reshape(nx + 1, ny + 1, nz + 1)
    corner = ids[:-1, :-1, :-1].ravel()
    offset = {b: ids[b[0]:nx + b[0], b[1]:ny + b[1], b[2]:nz + b[2]].ravel()
              - corner for b in itertools.product((0, 1), repeat=3)}
    tets = []
    for perm in itertools.permutations(range(3)):       # 6 paths 000→111
        path, bits = [(0, 0, 0)], [0, 0, 0]
        for axis in perm:
            bits[axis] = 1
            path.append(tuple(bits))
        tets.append(np.stack([corner + offset[b] for b in path], axis=1))
    tets = np.concatenate(tets)
    fix = np.linalg.det(np.concatenate(
        [np.ones((len(tets), 4, 1)), nodes[tets]], axis=2)) < 0
    tets[fix] = tets[fix][:, [1, 0, 2, 3]]              # positive volume
    return nodes, tets


def rectangle(n, lengths=(1.0, 1.0)):
    """Structured triangle mesh of [0, Lx]×[0, Ly] (each square split along
    its diagonal (0,0)-(1,1)). Returns (nodes, triangles)."""
    nx, ny = n
    axes = [np.linspace(0, L, m + 1) for L, m in zip(lengths, n)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 2)
    ids = np.arange(len(nodes)).reshape(nx + 1, ny + 1)
    a, b = ids[:-1, :-1].ravel(), ids[1:, :-1].ravel()
    c, d = ids[1:, 1:].ravel(), ids[:-1, 1:].ravel()
    return nodes, np.concatenate([np.stack([a, b, c], 1),
                                  np.stack([a, c, d], 1)])


def extrude(nodes2, triangles, thickness):
    """One layer of prisms over a 2D triangle mesh, each split into 3
    tetrahedra by the rule "lowest vertex id first" (conforming)."""
    n = len(nodes2)
    nodes = np.concatenate([np.column_stack([nodes2, np.zeros(n)]),
                            np.column_stack([nodes2, np.full(n, thickness)])])
    t = np.sort(triangles, axis=1)                       # a < b < c
    a, b, c = t.T
    A, B, C = a + n, b + n, c + n
    tets = np.concatenate([np.stack([a, b, c, C], 1), np.stack([a, b, B, C], 1),
                           np.stack([a, A, B, C], 1)])
    fix = np.linalg.det(np.concatenate(
        [np.ones((len(tets), 4, 1)), nodes[tets]], axis=2)) < 0
    tets[fix] = tets[fix][:, [1, 0, 2, 3]]
    return nodes, tets


def mesh_problem(nodes, cells, K, prescribed, contact_nodes, faces):
    """A ContactProblem (kind "mesh") from the full K: ``prescribed`` (n, d)
    holds Dirichlet values and NaN at free DOFs; f = −K_fD u_D."""
    n, d = nodes.shape
    free = np.isnan(prescribed).ravel()
    u_D = np.nan_to_num(prescribed).ravel()
    K = sp.csr_matrix(K)
    Kr = K[free][:, free].tocsr()
    f = -(K[free] @ u_D)
    dof_map = np.column_stack(np.divmod(np.flatnonzero(free), d))
    reduced = np.full(n * d, -1)
    reduced[free] = np.arange(free.sum())
    contact_dofs = reduced.reshape(n, d)[contact_nodes]
    M = surface_mass(nodes, faces, contact_nodes)
    return ContactProblem(K=Kr, f=f, M=M, contact_dofs=contact_dofs,
                          meta={}, nodes=nodes, cells=cells,
                          dof_map=dof_map,
                          u_prescribed=np.nan_to_num(prescribed).reshape(n, d),
                          contact_nodes=np.asarray(contact_nodes))
