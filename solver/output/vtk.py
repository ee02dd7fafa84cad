"""VTK output for ParaView (written with meshio): the deformed body of a
frictionless solve (``result.vtu``) and one file per load step of a
friction run with a ``result.pvd`` index.

Cells: triangles in 2D, tetrahedra (meshio ``"tetra"``) when the nodes have
3 coordinates. Point data: ``u`` (displacement, 3 components in 2D too, so
that ParaView's *Warp By Vector* applies it), and on the contact nodes (zero
elsewhere) ``contact_pressure`` (λ_i / D_ii), ``in_contact``; friction steps
add ``friction_traction``, ``stick`` and ``slip``; ``initial_gap`` is NaN off
Γc. A contact field given per contact node as a vector (shape (Nc, k), e.g.
the tangential traction in 3D) is written as a k-component point field; 2D
files are unchanged by the 3D support.
"""

import numpy as np

__all__ = ["result_mesh", "step_mesh", "write_vtk", "write_pvd"]


def _points(problem):
    nodes = problem.nodes
    if nodes.shape[1] == 3:
        return nodes
    return np.c_[nodes, np.zeros(len(nodes))]


def _cells(problem):
    """meshio cell block: triangles in 2D, tetrahedra in 3D."""
    kind = "tetra" if problem.nodes.shape[1] == 3 else "triangle"
    return [(kind, problem.cells)]


def _vectors(values, n):
    """(n, 2) or (n, 3) vectors as (n, 3)."""
    values = np.asarray(values)
    if values.shape[1] == 3:
        return values
    return np.c_[values, np.zeros(n)]


def _on_nodes(problem, values, fill=0.0, dtype=float):
    values = np.asarray(values)
    out = np.full((len(problem.nodes),) + values.shape[1:], fill,
                  dtype=dtype)
    out[problem.contact_nodes] = values
    return out


def result_mesh(problem, result):
    """meshio.Mesh of a frictionless solve."""
    import meshio

    n = len(problem.nodes)
    data = {"u": _vectors(result.displacement, n),
            "contact_pressure": _on_nodes(problem, result.contact_pressure),
            "in_contact": _on_nodes(problem, result.in_contact, 0, np.int32),
            "initial_gap": _on_nodes(problem, result.gap, np.nan)}
    return meshio.Mesh(_points(problem), _cells(problem), point_data=data)


def step_mesh(problem, fields):
    """meshio.Mesh of one friction load step (``fields`` of the step)."""
    import meshio

    n = len(problem.nodes)
    data = {"u": _vectors(fields["displacement"], n)}
    for name, fill, dtype in (("contact_pressure", 0.0, float),
                              ("friction_traction", 0.0, float),
                              ("in_contact", 0, np.int32),
                              ("stick", 0, np.int32), ("slip", 0, np.int32)):
        data[name] = _on_nodes(problem, fields[name], fill, dtype)
    cell_data = None
    if getattr(problem, "is_mortar", False):  # two bodies: the body,
        # the interface traction
        body = np.asarray(problem.body)
        data["body"] = body
        data["traction"] = _vectors(_on_nodes(problem, fields["traction"]),
                                    n)
        cell_data = {"body": [body[problem.cells[:, 0]]]}
    return meshio.Mesh(_points(problem), _cells(problem), point_data=data,
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
