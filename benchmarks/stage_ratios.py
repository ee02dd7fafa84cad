"""Ratios to the fastest floor from JSON lines of ``measure.py`` runs.

Each line: ``{"size": NAME, "stage": STAGE, "backend": B, "out": <the JSON
that measure.py printed>}`` (the PERF17 runs in ``README.md`` were made
with a shell loop writing such lines). Prints, per size, every floor and
every other stage as wall and CPU time, each the shortest of its repeats,
with its ratio to the fastest floor by the same clock.

Usage::

    python benchmarks/stage_ratios.py LOG.jsonl [LOG2.jsonl ...]
"""

import json, sys, collections
rows = [json.loads(l) for f in sys.argv[1:] for l in open(f)]
by = collections.defaultdict(lambda: collections.defaultdict(list))
dofs = {}
for r in rows:
    by[r["size"]][(r["stage"], r["backend"])].append(r["out"])
    dofs[r["size"]] = r["out"]["dofs"]
for size, st in by.items():
    best = lambda k, key: min(o[key] for o in st[k])
    floors = {b: (best(("floor", b), "time"), best(("floor", b), "cpu")) for (s, b) in st if s == "floor"}
    fw = min(floors, key=lambda b: floors[b][0]); fc = min(floors, key=lambda b: floors[b][1])
    print(f"{size} DOFs {dofs[size]}: floors " + ", ".join(f"{b} {w:.3f} s wall / {c:.3f} s CPU" for b, (w, c) in floors.items()) + f"; fastest wall {fw}, CPU {fc}")
    for (s, b), outs in sorted(st.items()):
        if s == "floor": continue
        w, c = best((s, b), "time"), best((s, b), "cpu")
        print(f"   {s:22s} {b:8s} wall {w:7.3f} ({w / floors[fw][0]:.2f})  CPU {c:7.3f} ({c / floors[fc][1]:.2f})  J/F {outs[0].get('J')}/{outs[0].get('F')} n={len(outs)}")
