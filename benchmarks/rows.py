"""One size of the benchmark: its measurements and its table row (the
columns are explained in ``run.py``'s docstring)."""

from processes import measure, output_stage

__all__ = ["columns", "measure_size"]

METHODS = ("min", "fb")


def columns(backends):
    """The table's column names for the measured ``backends``."""
    return (["DOFs", "Nc", "export [s]", "export RSS [MB]"]
            + [f"floor {b} [s]" for b in backends] + ["fastest"]
            + [f"{m} {b} [s] (/floor)" for m in METHODS for b in backends]
            + ["levels", "min J/F (finest)", "fb J/F (finest)",
               "Schur [s]", "output [s]", "Clarabel [s] (/min)",
               "SfePy SSN [s] (/min)", "SfePy J", "friction [s] (/floor)",
               "friction J/F", "RSS floor [MB]", "RSS Schur [MB]",
               "RSS Newton [MB]", "RSS output [MB]", "Newton/floor RSS",
               "friction RSS [MB]"])


def _best(runs):
    """The fastest of repeated runs, with the largest peak RSS of them."""
    best = dict(min(runs, key=lambda r: r["time"]))
    best["peak_rss_mb"] = max(r["peak_rss_mb"] for r in runs)
    return best


def _counts(r):
    return f"{r['J']}/{r['F']} ({r['J_finest']})"


def measure_size(npz, args, scratch):
    """Measure every stage of one problem file; the row's cells (dict)."""
    backends, runs = args.backends, {}
    for _ in range(args.repeat):  # rounds: noise spreads over backends
        for b in backends:
            for stage in ("floor",) + METHODS:
                runs.setdefault((stage, b), []).append(
                    measure(npz, stage, b))
    best = {key: _best(value) for key, value in runs.items()}
    fastest = min(backends, key=lambda b: best["floor", b]["time"])
    floor = best["floor", fastest]
    t0 = floor["time"]
    cells = {"DOFs": floor["dofs"], "Nc": floor["nc"], "fastest": fastest,
             "RSS floor [MB]": f"{floor['peak_rss_mb']:.0f}"}
    for b in backends:
        cells[f"floor {b} [s]"] = f"{best['floor', b]['time']:.3g}"
    for m in METHODS:
        for b in backends:
            r = best[m, b]
            cells[f"{m} {b} [s] (/floor)"] = \
                f"{r['time']:.3g} ({r['time'] / t0:.2f})" + \
                ("" if r["converged"] else " not converged")
        ours = best[m, fastest]
        cells["levels"] = str(ours["levels"])
        cells[f"{m} J/F (finest)"] = _counts(ours) + "".join(
            f"; {b} {_counts(best[m, b])}" for b in backends
            if _counts(best[m, b]) != _counts(ours))
    newton = max(best[m, fastest]["peak_rss_mb"] for m in METHODS)
    cells["RSS Newton [MB]"] = f"{newton:.0f}"
    cells["Newton/floor RSS"] = f"{newton / floor['peak_rss_mb']:.2f}"
    schur = measure(npz, "schur", fastest)
    cells["Schur [s]"] = f"{schur['time']:.3g}"
    cells["RSS Schur [MB]"] = f"{schur['peak_rss_mb']:.0f}"
    seconds, rss = output_stage(npz, fastest, scratch)
    cells["output [s]"], cells["RSS output [MB]"] = \
        f"{seconds:.3g}", f"{rss:.0f}"
    cells.update(_peers(npz, args, fastest, best["min", fastest]["time"],
                        floor["dofs"]))
    if floor["dofs"] <= args.max_friction_dofs:
        r = measure(npz, "friction", fastest, args.steps)
        cells["friction [s] (/floor)"] = \
            f"{r['time']:.3g} ({r['time'] / t0:.1f})" + \
            ("" if r["converged"] else " not converged")
        cells["friction J/F"] = f"{r['J']}/{r['F']}"
        cells["friction RSS [MB]"] = f"{r['peak_rss_mb']:.0f}"
    return cells


def _peers(npz, args, fastest, ours, dofs):
    """Clarabel's and SfePy's cells, compared with our φ_min (``ours`` s)."""
    cells = {}
    for peer in args.peers:
        dofs_max = args.max_sfepy_dofs if peer == "sfepy" \
            else args.max_peer_dofs
        if dofs > dofs_max:
            continue
        r = measure(npz, peer, fastest)
        name = "Clarabel [s] (/min)" if peer == "clarabel" \
            else "SfePy SSN [s] (/min)"
        cells[name] = f"{r['time']:.3g} " + (
            f"({r['time'] / ours:.1f})" if r["agreement"] <= 1e-6
            else f"(differs {r['agreement']:.0e})")
        if peer == "sfepy":
            cells["SfePy J"] = str(r["J"])
    return cells
