"""VTK output for ParaView (written with meshio): the deformed body of a
frictionless solve (``result.vtu``) and one file per load step of a
friction run with a ``result.pvd`` index; the point data are listed in
docs/results.md ("VTK"). Cells: the problem's own, triangles or
quadrilaterals (VTK_QUAD, 9) in 2D, tetrahedra or hexahedra
(VTK_HEXAHEDRON, 12) in 3D. A contact field given per contact node as a vector
(shape (Nc, k)) is written as a k-component point field; the 3D friction
traction, components in per-node tangent frames, as the 3-vector
Σ_k g_k τ_k when the frames are given (:func:`step_mesh`)."""

import numpy as np

__all__ = ["result_mesh", "step_mesh", "traction_vectors", "write_vtk",
           "write_pvd"]


def vtk_points(problem):
    nodes = problem.nodes
    if nodes.shape[1] == 3:
        return nodes
    return np.c_[nodes, np.zeros(len(nodes))]


def vtk_cells(problem):
    """meshio cell block of the problem's cells (module docstring)."""
    kind = {(2, 3): "triangle", (2, 4): "quad", (3, 4): "tetra",
            (3, 8): "hexahedron"}[problem.nodes.shape[1],
                                  np.shape(problem.cells)[1]]
    return [(kind, problem.cells)]


def vtk_vectors(values, n):
    """(n, 2) or (n, 3) vectors as (n, 3)."""
    values = np.asarray(values)
    if values.shape[1] == 3:
        return values
    return np.c_[values, np.zeros(n)]


def on_nodes(problem, values, fill=0.0, dtype=float):
    values = np.asarray(values)
    out = np.full((len(problem.nodes),) + values.shape[1:], fill,
                  dtype=dtype)
    out[problem.contact_nodes] = values
    return out


def result_mesh(problem, result):
    """meshio.Mesh of a frictionless solve."""
    import meshio

    n = len(problem.nodes)
    data = {"u": vtk_vectors(result.displacement, n),
            "contact_pressure": on_nodes(problem, result.contact_pressure),
            "in_contact": on_nodes(problem, result.in_contact, 0, np.int32),
            "initial_gap": on_nodes(problem, result.gap, np.nan)}
    return meshio.Mesh(vtk_points(problem), vtk_cells(problem), point_data=data)


def traction_vectors(traction, tangents):
    """The tangential traction as vectors in x, y, z: Σ_k g_k τ_k per
    contact node from its components g (Nc, d − 1) in the tangent frames
    ``tangents`` (Nc, d − 1, d); 0 where the frame is NaN (supports)."""
    g = np.asarray(traction, float).reshape(len(tangents), -1)
    return np.einsum("ik,ikd->id", g, np.nan_to_num(tangents))


def step_mesh(problem, fields, tangents=None):
    """meshio.Mesh of one friction load step (its ``fields``); with the
    tangent frames over Γc (``tangents``) a 3D step's ``friction_traction``
    as a 3-vector in x, y, z (:func:`traction_vectors`)."""
    import meshio

    n = len(problem.nodes)
    data = {"u": vtk_vectors(fields["displacement"], n)}
    for name, fill, dtype in (("contact_pressure", 0.0, float),
                              ("friction_traction", 0.0, float),
                              ("in_contact", 0, np.int32),
                              ("stick", 0, np.int32), ("slip", 0, np.int32)):
        data[name] = on_nodes(problem, fields[name], fill, dtype)
    if tangents is not None and np.shape(tangents)[-1] == 3:
        data["friction_traction"] = on_nodes(problem, traction_vectors(
            fields["friction_traction"], tangents))
    cell_data = None
    if getattr(problem, "is_mortar", False):  # two bodies: the body,
        # the interface traction
        body = np.asarray(problem.body)
        data["body"] = body
        data["traction"] = vtk_vectors(on_nodes(problem, fields["traction"]),
                                    n)
        cell_data = {"body": [body[problem.cells[:, 0]]]}
    return meshio.Mesh(vtk_points(problem), vtk_cells(problem), point_data=data,
                       cell_data=cell_data)


def write_vtk(path, result, problem):
    """``result.vtu`` of a frictionless solve, written atomically."""
    import meshio

    from .folder import atomic_path

    with atomic_path(path) as tmp:
        meshio.write(tmp, result_mesh(problem, result), file_format="vtu")


def write_pvd(path, timesteps):
    """A ParaView collection: ``timesteps`` = [(load factor, file name)].
    The load factor is written as a plain decimal number."""
    from xml.sax.saxutils import quoteattr

    entries = "".join(
        f"    <DataSet timestep=\"{float(t)!s}\" file={quoteattr(name)}/>\n"
        for t, name in timesteps)
    with open(path, "w") as stream:
        stream.write('<?xml version="1.0"?>\n<VTKFile type="Collection" '
                     'version="0.1">\n  <Collection>\n' + entries
                     + "  </Collection>\n</VTKFile>\n")
