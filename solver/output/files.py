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
           "summary_of", "friction_summary_of", "write_friction_result",
           "write_vtk_series"]


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
        "system": "condensed" if result.get("condensed") else "full",
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
        "start": result.get("start", "zero"),
        # nested start: per level, coarsest first (n_nodes, nit, njev, nfev,
        # success, time); the counts above include them all
        "levels": [dict(level) for level in result.get("levels", [])],
        "wall_time": float(result.time),
        # ‖Φ‖ before each iteration (as printed on a failure, and as in a
        # friction step's record; the final one is "residual"); result.npz
        # holds the full per-iteration history
        "residual_history": [float(r) for r in history["residual"]],
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
        contact_pressure_consistent=result.contact_pressure_consistent,
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


def friction_summary_of(result, problem, **extra):
    """The ``summary.json`` fields of a friction run (Table 2's metrics)."""
    summary = {
        "problem": problem.source,
        "kind": problem.kind,
        "mode": "friction",
        "friction": result.friction,
        "steps": result.steps,
        "steps_completed": int(result.steps_completed),
        "failed_step": result.failed_step,
        "formulation": result.formulation,
        "coulomb": result.coulomb,
        "method": result.method,
        "gap": result.gap_mode,
        "system": "condensed" if result.get("condensed") else "full",
        "converged": bool(result.success),
        "message": result.message,
        "n_jacobian": int(result.njev),
        "n_residual": int(result.nfev),
        "iterations": int(result.nit),
        "gradient_steps": int(sum(r["gradient_steps"]
                                  for r in result.records)),
        "n_dof": int(problem.n_dofs),
        "wall_time": float(result.time),
        "per_step": result.records,
    }
    if result.steps_completed:
        summary.update(
            final_n_contact=int(result.in_contact[-1].sum()),
            final_n_stick=int(result.stick[-1].sum()),
            final_n_slip=int(result.slip[-1].sum()),
            final_max_contact_pressure=float(
                result.contact_pressure[-1].max()))
    summary.update(extra)
    return summary


def write_friction_result(path, result, problem):
    """``result.npz`` of a friction run: per-step fields (first axis =
    completed load steps) and per-step counts."""
    records = result.records[:result.steps_completed]
    arrays = {key: result[key] for key in (
        "load_factor", "u", "displacement", "contact_force",
        "contact_pressure", "friction_traction", "friction_bound",
        "tangential_displacement", "in_contact", "stick", "slip")}
    arrays.update(
        contact_nodes=(problem.contact_nodes if problem.kind == "mesh"
                       else np.arange(problem.n_contact)),
        step_njev=np.array([r["njev"] for r in records], dtype=np.int64),
        step_nfev=np.array([r["nfev"] for r in records], dtype=np.int64),
        converged=np.array(bool(result.success)),
        steps_completed=np.array(result.steps_completed))
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as stream:
            np.savez_compressed(stream, **arrays)


def write_vtk_series(folder, result, problem):
    """One ``.vtu`` per completed load step and a ParaView ``.pvd`` index."""
    import meshio

    os.makedirs(os.path.join(folder, "steps"), exist_ok=True)
    n = len(problem.nodes)
    points = np.c_[problem.nodes, np.zeros(n)]
    entries = []
    for k in range(result.steps_completed):
        data = {"u": np.c_[result.displacement[k], np.zeros(n)]}
        for name, fill, dtype in (("contact_pressure", 0.0, float),
                                  ("friction_traction", 0.0, float),
                                  ("in_contact", 0, np.int32),
                                  ("stick", 0, np.int32),
                                  ("slip", 0, np.int32)):
            values = np.full(n, fill, dtype=dtype)
            values[problem.contact_nodes] = result[name][k]
            data[name] = values
        name = os.path.join("steps", f"step_{k + 1:04d}.vtu")
        mesh = meshio.Mesh(points, [("triangle", problem.cells)],
                           point_data=data)
        with atomic_path(os.path.join(folder, name)) as tmp:
            meshio.write(tmp, mesh, file_format="vtu")
        entries.append(f'    <DataSet timestep="{result.load_factor[k]!r}" '
                       f'file="{name}"/>')
    pvd = ('<?xml version="1.0"?>\n<VTKFile type="Collection" '
           'version="0.1">\n  <Collection>\n' + "\n".join(entries)
           + "\n  </Collection>\n</VTKFile>\n")
    with atomic_path(os.path.join(folder, "result.pvd")) as tmp:
        with open(tmp, "w") as stream:
            stream.write(pvd)
