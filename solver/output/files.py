"""Result files of a solve: ``summary.json``, ``result.npz`` and VTK.

Every file is written to a temporary name in the output folder and renamed
when complete, so an interrupted run never leaves a half-written file.
"""

import contextlib
import json
import os
import tempfile

import numpy as np

__all__ = ["atomic_path", "write_summary", "write_result", "write_vtk",
           "summary_of"]


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it over ``path`` on
    success, delete it on failure."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    suffix = os.path.splitext(path)[1]
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=suffix, dir=folder)
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def summary_of(result, problem, **extra):
    """The ``summary.json`` fields of a frictionless solve."""
    history = result.history
    summary = {
        "problem": problem.source,
        "kind": problem.kind,
        "method": result.method,
        "gap": result.gap_mode,
        "converged": bool(result.success),
        "status": int(result.status),
        "message": result.message,
        "iterations": int(result.nit),
        "n_jacobian": int(result.njev),
        "n_residual": int(result.nfev),
        "residual": float(result.residual),
        "error": float(result.error),
        "complementarity": float(result.complementarity),
        "n_contact_nodes": int(result.n_contact),
        "max_contact_pressure": float(np.max(result.contact_pressure)),
        "max_contact_force": float(np.max(result.contact_force)),
        "n_dof": int(problem.n_dofs),
        "n_contact_candidates": int(np.isfinite(result.gap).sum()),
        "line_search_failures": int(sum(history["line_search_failed"])),
        "gradient_steps": int(sum(s == "gradient" for s in history["step"])),
        "gap_scale": float(result.gap_scale),
        "wall_time": float(result.time),
    }
    summary.update(extra)
    return summary


def write_summary(path, summary):
    with atomic_path(path) as tmp:
        with open(tmp, "w") as stream:
            json.dump(summary, stream, indent=2)
            stream.write("\n")


def write_result(path, result, problem):
    """``result.npz``: fields along Γc, nodal displacement and history."""
    history = result.history
    arrays = dict(
        u=result.u, displacement=result.displacement,
        contact_nodes=(problem.contact_nodes if problem.kind == "mesh"
                       else np.arange(problem.n_contact)),
        gap=result.gap, normal=result.normal,
        contact_force=result.contact_force,
        contact_pressure=result.contact_pressure,
        contact_pressure_lumped=result.contact_pressure_lumped,
        normal_displacement=result.normal_displacement,
        in_contact=result.in_contact,
        converged=np.array(bool(result.success)),
        history_residual=np.array(history["residual"], dtype=float),
        history_error=np.array(history["error"], dtype=float),
        history_alpha=np.array(history["alpha"], dtype=float),
        history_step=np.array(history["step"], dtype=str),
        history_active=np.array(history["active"], dtype=np.int64),
        history_line_search_failed=np.array(history["line_search_failed"],
                                            dtype=bool))
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as stream:
            np.savez_compressed(stream, **arrays)


def write_vtk(path, result, problem):
    """A VTK unstructured grid (meshio) with u, contact pressure and mask."""
    import meshio

    n = len(problem.nodes)
    points = np.c_[problem.nodes, np.zeros(n)]
    displacement = np.c_[result.displacement, np.zeros(n)]
    pressure = np.zeros(n)
    pressure[problem.contact_nodes] = result.contact_pressure
    mask = np.zeros(n, dtype=np.int32)
    mask[problem.contact_nodes[result.in_contact]] = 1
    gap = np.full(n, np.nan)
    gap[problem.contact_nodes] = result.gap
    mesh = meshio.Mesh(points, [("triangle", problem.cells)],
                       point_data={"u": displacement,
                                   "contact_pressure": pressure,
                                   "in_contact": mask, "initial_gap": gap})
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")
