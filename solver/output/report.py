"""Readable text of the command line: the ``--info`` summary and the
summaries of a frictionless solve and of a friction run, from the same
dictionaries as ``summary.json``; a number may be infinite or NaN, or
already the string ``"inf"``/``"nan"`` read back from disk, and
:func:`_g`, :func:`_e` print either as it is."""

import json

__all__ = ["format_summary", "format_result", "format_friction_result"]


def format_summary(info):
    """The ``--info`` summary as readable lines."""
    meta = info["meta"]
    lines = [f"problem kind      {info['kind']}",
             f"reduced DOFs      {info['dofs']}",
             f"contact nodes Nc  {info['contact_nodes']} "
             f"({info['contact_nodes_free']} free, "
             f"{info['contact_nodes'] - info['contact_nodes_free']} "
             "supported)",
             f"K                 nnz {info['K_nnz']}, "
             f"‖K‖_F = {_g(info['K_norm_fro'])}, "
             f"max |K_ij| = {_g(info['K_norm_max'])}",
             f"‖f‖               {_g(info['f_norm'])}",
             f"sum of M          {_g(info['M_sum'], '.12g')}"]
    if info["kind"] == "mesh" and "bodies" in info:  # two bodies
        facet = "segments" if info.get("dim", 2) == 2 else "triangles"
        cells = "triangles" if info.get("dim", 2) == 2 else "tetrahedra"
        lines += [f"mesh              {meta.get('mesh')}: "
                  f"{info[cells]} {cells}, {info['nodes']} nodes, "
                  f"{info['bodies']} bodies",
                  *(f"body {i}            {b.get('name')}: "
                    f"E = {_g(b['E'], 'g')}, nu = {_g(b['nu'], 'g')}"
                    for i, b in enumerate(meta["bodies"])),
                  f"interface         {info['pairs']} pair(s), "
                  f"{info[f'slave_{facet}']} slave {facet} (body "
                  f"{meta['slave_body']}), {info[f'master_{facet}']} master "
                  f"{facet} (body {meta['master_body']})"]
    elif info["kind"] == "mesh" and info.get("dim", 2) == 3:
        lines += [f"mesh              {meta.get('mesh')}: "
                  f"{_cells(info)}, {info['nodes']} nodes, "
                  f"{info['contact_faces']} contact "
                  + ("quadrilaterals" if "hexahedra" in info else
                     "triangles"),
                  f"material          E = {_g(meta['E'], 'g')}, "
                  f"nu = {_g(meta['nu'], 'g')}",
                  "obstacle          " + json.dumps(info["obstacle"],
                                                    sort_keys=True)]
    elif info["kind"] == "mesh":
        obstacle = info["obstacle"]  # [x(t), y(t)], a polyline's repr,
        # or {"curves": [...]} (several)
        if isinstance(obstacle, (list, tuple)):
            x, y = obstacle
            obstacle = f"x(t) = {x}, y(t) = {y}"
        elif isinstance(obstacle, dict):
            obstacle = json.dumps(obstacle, sort_keys=True)
        rng = info["obstacle_t_range"]
        lines += [f"mesh              {meta.get('mesh')}: "
                  f"{_cells(info)}, {info['nodes']} nodes",
                  f"material          E = {_g(meta['E'], 'g')}, "
                  f"nu = {_g(meta['nu'], 'g')},"
                  f" plane {meta['plane']}",
                  f"obstacle          {obstacle}"
                  + ("" if rng is None else f", t in [{rng[0]}, {rng[1]}]")]
    else:
        lines += [f"description       {meta['description']}",
                  f"gaps s            {info['gap']}",
                  f"normals           {info['normal']}"]
    if "load" in meta:
        lines.append(f"load              {json.dumps(meta['load'])}")
    if "refusals" in info:  # what a solve would refuse
        verdict = ("passed" if not info["refusals"] else
                   "a solve would refuse this problem (error below)")
        lines.append(f"checks            {', '.join(info['checks'])}: "
                     f"{verdict}")
    return "\n".join(lines)


def format_friction_result(summary, outdir):
    """A readable summary of a friction run."""
    state = "converged" if summary["converged"] else "NOT CONVERGED"
    lines = [
        f"f_c = {_g(summary['friction'], 'g')}, {summary['steps']} load "
        "steps, "
        f"{summary['formulation']} formulation, {summary['coulomb']} "
        f"normal force, {summary['method']} method: {state}",
        f"steps completed   {summary['steps_completed']} of "
        f"{summary['steps']}",
        f"evaluations       J {summary['n_jacobian']}, F "
        f"{summary['n_residual']} in total (thesis Table 2 metrics)",
        f"system            {_system_text(summary)}",
        *_reason_text(summary),
        f"gradient steps    {summary['gradient_steps']}",
        *verification_text(summary)]
    if summary["steps_completed"]:
        lines += [
            f"last step         {_nodes(summary['final_n_contact'])} in "
            f"contact: {summary['final_n_stick']} stick, "
            f"{summary['final_n_slip']} slip; max pressure "
            f"{_g(summary['final_max_contact_pressure'])}"]
    lines += _force_lines({"rigid_body_motion":
                           summary.get("rigid_body_motion")})
    lines += [f"reduced DOFs      {summary['n_dof']}",
              f"wall time         {_g(summary['wall_time'], '.3f')} s",
              f"outputs           {outdir}/"]
    return "\n".join(lines)


def _force_lines(summary):
    """The total contact force and, for a floating body, its rigid motion."""
    total = summary.get("total_contact_force") or []
    lines = []
    if total:
        lines.append("contact force     (" + ", ".join(_g(v) for v in total)
                     + ") in total, on the body")
    rigid = summary.get("rigid_body_motion")
    if rigid:
        lines.append(
            f"rigid-body motion translation (" + ", ".join(
                _g(v) for v in rigid["translation"]) + "), rotation ("
            + ", ".join(_g(v) for v in rigid["rotation"]) + ") rad "
            f"({rigid['modes']} modes held by contact only)")
        for weak in rigid.get("weakly_held") or []:
            lines.append(f"weakly held       {weak['motion']} (normals see "
                         f"{_g(weak['ratio'], '.2g')} of it: set by the mesh)")
    return lines


def _system_text(summary):
    if summary.get("linear_solver") == "amg":
        krylov = summary.get("krylov_per_system") or []
        most = f"at most {max(krylov)} per Newton system" if krylov else \
            f"{summary.get('n_jacobian')} Newton systems"  # friction
        return ("full primal system, active set method, AMG-preconditioned "
                f"CG ({summary.get('krylov_iterations')} CG iterations, "
                f"{most})")
    if summary["system"] == "full" and summary.get("rigid_body_motion"):
        return ("full (in all unknowns; the DOFs that hold the rigid-body "
                "modes replaced by the modes' amplitudes)")
    if summary["system"] == "full":
        return ("full (the thesis's, in all unknowns)"
                if _table1_applies(summary) else "full (in all unknowns)")
    candidates = summary.get("normal_candidates")
    if candidates:
        rounds = candidates["rounds"]
        return (f"condensed onto the normal unknowns of "
                f"{candidates['n_candidates']} candidate nodes "
                f"({len(rounds)} round{'s' if len(rounds) > 1 else ''}; "
                "--system full: all unknowns)")
    text = ("condensed onto the contact boundary (--system full: "
            + ("the thesis's)" if _table1_applies(summary) else
               "all unknowns)"))
    levels = summary.get("levels") or []
    if len(levels) > 1:
        text += (f"\nnested start      {len(levels)} levels of "
                 f"{levels[0]['n_nodes']}..{levels[-1]['n_nodes']} contact "
                 f"nodes; J per level {[lv['njev'] for lv in levels]}")
    return text


def _reason_text(summary):
    """The linear solver and why, when ``auto`` estimated the factor's
    memory or ``amg`` was given (empty otherwise)."""
    reason = summary.get("linear_solver_reason")
    if not reason:
        return []
    return [f"linear solver     {summary['linear_solver']} ({reason})"]


def _nodes(count):
    """"1 node", "4 nodes"."""
    return f"{count} node" + ("" if count == 1 else "s")


def _counts_note(summary):
    """What the J and F counts cover: a nested start's levels, and where
    Table 1 applies (a 2D rigid obstacle: the nested start is 2D only) how
    to get its counts."""
    if summary["system"] == "full":
        return "  (thesis Table 1 metrics)" if _table1_applies(summary) \
            else ""
    if summary.get("start") != "nested":
        return ""
    if _table1_applies(summary):
        return "  (all levels; Table 1's: --system full)"
    return "  (all levels)"


def _table1_applies(summary):
    """Whether the thesis's system and Tables 1 and 2 apply: a 2D body on
    a rigid obstacle (gaps from the obstacle or the body), not two
    bodies, a discrete problem or 3D."""
    return (summary.get("kind") == "mesh"
            and summary.get("gap") in ("obstacle", "body")
            and summary.get("dim", 2) == 2)


def _e(value):
    """A number in %.3e, or as written ("inf", "nan")."""
    return _g(value, ".3e")


def _g(value, spec=".6g"):
    """A number in ``spec``, or anything else (``"inf"``, None) as text."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return format(value, spec)
    return str(value)


def stopping_text(summary):
    """The stopping test as applied: measure ≤ tol × scale."""
    stop = summary.get("stopping") or {}
    if "absolute" not in stop:
        return "-"
    return (f"{_e(stop['absolute'])} <= tol {_e(stop['tol'])} x scale "
            f"{_e(stop['scale'])} (relative {_e(stop['relative'])}; "
            f"{stop.get('test', '')})")


def verification_text(summary):
    """One line on the checks of the answer (empty if none were made)."""
    checks = summary.get("verification") or {}
    if not checks:
        return []
    failed = checks.get("failed") or []
    state = "passed" if checks.get("passed") else (
        "FAILED" + (": " + ", ".join(failed) if failed else ""))
    return [f"verification      {state}"]


def format_result(summary, outdir):
    """A readable summary of a solve."""
    state = "converged" if summary["converged"] else "NOT CONVERGED"
    lines = [
        f"{summary['method']} method, gap from {summary['gap']}: {state} "
        f"({summary['message']})",
        f"iterations        {summary['iterations']}",
        f"evaluations       J {summary['n_jacobian']}, F "
        f"{summary['n_residual']}" + _counts_note(summary),
        f"system            {_system_text(summary)}",
        *_reason_text(summary),
        f"stopping test     {stopping_text(summary)}",
        f"final ||Phi||     {_e(summary['residual'])}",
        *verification_text(summary),
        f"complementarity   max|min(lambda, s - u_n)| = "
        f"{_e(summary['complementarity'])}",
        f"contact nodes     {summary['n_contact_nodes']} in contact, of "
        f"{summary['n_contact_candidates']} contact nodes that can touch "
        "(not on a support)",
        f"max pressure      {_g(summary['max_contact_pressure'])} "
        "(lumped, lambda_i / D_ii)",
        *_force_lines(summary),
        f"reduced DOFs      {summary['n_dof']}",
        f"wall time         {_g(summary['wall_time'], '.3f')} s",
        f"outputs           {outdir}/"]
    return "\n".join(lines)


def _cells(info):
    """"454 triangles" (or quadrilaterals, tetrahedra, hexahedra) of a
    ``summary()``."""
    name = next(k for k in ("triangles", "quadrilaterals", "tetrahedra",
                            "hexahedra") if k in info)
    return f"{info[name]} {name}"
