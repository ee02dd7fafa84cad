"""Result files of a solve: ``summary.json``, ``result.npz`` and VTK,
each written to a temporary name in the output folder and renamed when
complete (docs/results.md lists their contents).

``summary.json`` is strict JSON whatever the solve produced: a legal but
extreme problem may overflow to infinite or NaN numbers, which
:func:`write_summary` writes, at any depth, as the strings ``"inf"``,
``"-inf"`` or ``"nan"`` (:func:`json_ready`)."""

import json
import math

import numpy as np

from .folder import atomic_path

__all__ = ["write_summary", "write_result", "summary_of",
           "friction_summary_of", "json_ready", "frames_on_contact",
           "result_arrays", "write_arrays"]


def frames_on_contact(problem, geometry):
    """The gaps, unit normals and tangents of ``geometry`` over all of Γc,
    in the order of ``problem.contact_nodes`` (NaN at the nodes that take no
    part): ``gap`` (Nc,), ``normal`` (Nc, d) and ``tangents`` (Nc, d − 1, d),
    the frame of a friction run's tangential fields."""
    nc, d = problem.n_contact, geometry.normal.shape[1]
    gap = np.full(nc, np.nan)
    normal = np.full((nc, d), np.nan)
    tangents = np.full((nc, d - 1, d), np.nan)
    gap[geometry.index] = geometry.gap
    normal[geometry.index] = geometry.normal
    tangents[geometry.index] = geometry.tangents
    return gap, normal, tangents


def _number(value):
    """A number of the summary as a Python float (possibly inf or NaN:
    :func:`write_summary` writes those as strings)."""
    return float(value)


def json_ready(value):
    """``value`` with every float made strict JSON (non-finite ones as
    ``"inf"``, ``"-inf"``, ``"nan"``), NumPy scalars and arrays as Python
    numbers and lists, at any depth (new objects)."""
    if isinstance(value, dict):
        return {key: json_ready(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(item) for item in value]
    if isinstance(value, np.ndarray):
        return json_ready(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else str(value)
    return value


def stopping_of(result, tol):
    """The stopping test that was applied, with the final values:
    ``result.stopping``, else that of :func:`solver.ncp.solve_ncp`."""
    stopping = result.get("stopping")
    if stopping is None:
        records = result.get("records") or [{}]
        error = result.get("error", records[-1].get("error", float("nan")))
        scale = result.get("scale", 1.0)
        stopping = {"test": "error <= tol * scale", "tol": tol,
                    "scale": scale, "absolute": error,
                    "relative": error / scale}
    return {key: (_number(value) if isinstance(value, (float, int,
                  np.floating, np.integer)) and not isinstance(value, bool)
                  else value) for key, value in dict(stopping).items()}


def verification_of(result):
    """``result.verification`` (the checks of the answer), its numbers as
    Python floats."""
    checks = dict(result.get("verification") or {})
    return {key: (_number(value) if isinstance(value, (float,
                  np.floating)) else value) for key, value in checks.items()}


def summary_of(result, problem, tol=None, **extra):
    """The ``summary.json`` fields of a frictionless solve."""
    history = result.history
    summary = {
        "problem": problem.source,
        "kind": problem.kind,
        "dim": int(problem.dim),
        "method": result.method,
        "gap": result.gap_mode,
        "system": "condensed" if result.get("condensed") else "full",
        "linear_solver": result.get("linear_solver"),
        # why backend "auto" took this path (None: no estimate was needed)
        "linear_solver_reason": result.get("linear_solver_reason"),
        "status": "converged" if result.success else "not_converged",
        "converged": bool(result.success),
        "ncp_status": int(result.status),
        "message": result.message,
        "stopping": stopping_of(result, tol),
        "verification": verification_of(result),
        "iterations": int(result.nit),
        "n_jacobian": int(result.njev),
        "n_residual": int(result.nfev),
        # ‖Φ‖ of the final iterate and the stopping test's measure of it
        "residual": _number(result.residual),
        "error": _number(result.error),
        "complementarity": _number(result.complementarity),
        "n_contact_nodes": int(result.n_contact),
        "max_contact_pressure": _number(np.max(result.contact_pressure)),
        "max_contact_force": _number(np.max(result.contact_force)),
        # Σ −λ_i ν_i, the obstacle's force on the body (a vector)
        "total_contact_force": [_number(v) for v in
                                result.get("total_contact_force", [])],
        # a body held by contact only: its rigid-body motion (else None)
        "rigid_body_motion": _rigid_body_of(result.get("rigid_body")),
        "n_dof": int(problem.n_dofs),
        "n_contact_candidates": int(np.isfinite(result.gap).sum()),
        # 3D: the nodes condensed onto (normal unknowns), per round
        "normal_candidates": _candidates_of(result.get("candidates")),
        "line_search_failures": int(sum(history["line_search_failed"])),
        "gradient_steps": int(sum(s == "gradient" for s in history["step"])),
        "gap_scale": float(result.gap_scale),
        # the iterative path: CG iterations in all and per Newton system
        "krylov_iterations": result.get("krylov"),
        "krylov_per_system": list(history.get("krylov", [])) or None,
        "start": result.get("start", "zero"),
        # nested start: per level, coarsest first (n_nodes, nit, njev, nfev,
        # success, time); the counts above include them all
        "levels": [dict(level) for level in result.get("levels", [])],
        "wall_time": float(result.time),
        # ‖Φ‖ before each iteration and, last, of the final iterate
        "residual_history": [_number(r) for r in history["residual"]]
        + [_number(result.residual)],
    }
    summary.update(extra, tol=tol)
    return summary


def _rigid_body_of(rigid):
    """The rigid-body motion of a floating body, JSON-safe (or None)."""
    if not rigid:
        return None
    return {"modes": int(rigid["modes"]),
            "translation": [_number(v) for v in rigid["translation"]],
            "rotation": [_number(v) for v in rigid["rotation"]],
            "alpha": [_number(v) for v in rigid["alpha"]],
            "start_touching_nodes": int(rigid["start_nodes"] or 0),
            # motions the contact normals see only weakly (WeaklyHeldWarning)
            "weakly_held": [{"motion": str(w["motion"]),
                             "ratio": _number(w["ratio"])}
                            for w in rigid.get("weakly_held") or []]}


def _candidates_of(candidates):
    """The candidate rounds of a 3D condensed solve, JSON-safe (or None)."""
    if not candidates:
        return None
    return {"n_candidates": int(candidates["n_candidates"]),
            "margin": _number(candidates["margin"]),
            "rounds": [{key: (_number(value) if isinstance(value, float)
                              else value) for key, value in r.items()}
                       for r in candidates["rounds"]],
            "enlarged": int(candidates["enlarged"]),
            "exhausted": bool(candidates["exhausted"])}


def write_summary(path, summary):
    """``summary.json``, written atomically; strict JSON: non-finite floats
    anywhere in ``summary`` are written as strings (:func:`json_ready`)."""
    text = json.dumps(json_ready(summary), indent=2, allow_nan=False)
    with atomic_path(path) as tmp:
        with open(tmp, "w") as stream:
            stream.write(text + "\n")


def result_arrays(result, problem):
    """The arrays of ``result.npz`` of a frictionless solve: fields along
    Γc, nodal displacement and the Newton history."""
    history = result.history
    return dict(
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


def write_arrays(path, arrays):
    """``arrays`` as an ``.npz`` archive, written atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as stream:
            np.savez_compressed(stream, **arrays)


def write_result(path, result, problem):
    """``result.npz``: fields along Γc, nodal displacement and history."""
    write_arrays(path, result_arrays(result, problem))


def friction_summary_of(result, problem, tol=None, **extra):
    """The ``summary.json`` fields of a friction run (Table 2's metrics)."""
    done = [r for r in result.records if r["converged"]]
    summary = {
        "problem": problem.source,
        "kind": problem.kind,
        "dim": int(problem.dim),
        "mode": "friction",
        "status": "converged" if result.success else "not_converged",
        "converged": bool(result.success),
        "message": result.message,
        "friction": result.friction,
        "steps": result.steps,
        "steps_completed": int(result.steps_completed),
        "failed_step": result.failed_step,
        "formulation": result.formulation,
        "coulomb": result.coulomb,
        "method": result.method,
        "gap": result.gap_mode,
        "system": "condensed" if result.get("condensed") else "full",
        "linear_solver": result.get("linear_solver"),
        "linear_solver_reason": result.get("linear_solver_reason"),
        "stopping": stopping_of(result, tol),
        "verification": verification_of(result),
        "n_jacobian": int(result.njev),
        "n_residual": int(result.nfev),
        "iterations": int(result.nit),
        "gradient_steps": int(sum(r["gradient_steps"]
                                  for r in result.records)),
        "n_dof": int(problem.n_dofs),
        # the iterative path: CG iterations in all (per step in per_step)
        "krylov_iterations": sum(r["krylov"] for r in result.records
                                 if "krylov" in r) if any(
            "krylov" in r for r in result.records) else None,
        # a body held by contact only: its rigid-body motion at the last
        # completed step (else None)
        "rigid_body_motion": _rigid_body_of(result.get("rigid_body")),
        "wall_time": float(result.time),
        "per_step": result.records,
    }
    if done:
        last = done[-1]
        summary.update(final_n_contact=last["n_contact"],
                       final_n_stick=last["n_stick"],
                       final_n_slip=last["n_slip"],
                       final_max_contact_pressure=last["max_pressure"])
    summary.update(extra, tol=tol)
    return summary
