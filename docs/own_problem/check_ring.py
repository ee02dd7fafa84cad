"""Check a solved ring (``ring.py``) against Lamé's closed form.

Reads the problem's ``meta`` (E, nu, a, b, gap, delta) from the ``.npz``
and the run's ``summary.json`` and ``result.npz`` (``docs/results.md``),
and compares the total contact force of the quarter ring with
p · πb/2, p the contact pressure of Lamé's thick-walled ring in plane
strain. Exit code 0 if the run converged, every contact node is in
contact and the force agrees to 1 %; 1 otherwise.

Usage::

    python check_ring.py ring.npz ring-solved
"""

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

#: Largest relative difference of the total contact force accepted.
TOLERANCE = 0.01


def lame_pressure(E, nu, a, b, gap, delta):
    """Contact pressure p of a ring a <= r <= b whose inner surface is
    moved out by delta and whose outer surface is held at u_r = gap (plane
    strain): u_r = A r + B / r, p = -sigma_rr(b)."""
    mu = E / (2 * (1 + nu))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    A = (gap * b - delta * a) / (b * b - a * a)
    B = delta * a - A * a * a
    return 2 * mu * B / b ** 2 - 2 * (lam + mu) * A


def free_expansion(nu, a, b, delta):
    """u_r(b) of the ring without the housing (sigma_rr(b) = 0)."""
    return 2 * delta * a * b * (1 - nu) / (a * a + (1 - 2 * nu) * b * b)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("problem", type=Path, help="the exported .npz")
    parser.add_argument("run", type=Path, help="the solver's output folder")
    args = parser.parse_args(argv)
    try:
        with np.load(args.problem) as problem:
            meta = json.loads(str(problem["meta"]))
        summary = json.loads((args.run / "summary.json").read_text())
        with np.load(args.run / "result.npz") as result:
            force = result["contact_force"]
            pressure = result["contact_pressure"]
            in_contact = result["in_contact"]
        E, nu, a, b = meta["E"], meta["nu"], meta["a"], meta["b"]
        gap, delta = meta["gap"], meta["delta"]
    except (OSError, KeyError, ValueError) as exc:
        parser.exit(1, f"check_ring.py: error: {exc!r} (a problem of ring.py "
                       "and its solver output folder?)\n")
    p = lame_pressure(E, nu, a, b, gap, delta)
    total, expected = force.sum(), p * math.pi * b / 2
    error = total / expected - 1
    inner = pressure[1:-1] / p - 1  # without the ends on the symmetry lines
    print(f"solver: {summary['status']}, verification "
          f"{'passed' if summary['verification']['passed'] else 'FAILED'}, "
          f"{int(in_contact.sum())} of {len(in_contact)} contact nodes in "
          "contact")
    print(f"Lamé: free expansion {free_expansion(nu, a, b, delta):.4g} > gap "
          f"{gap:g}, contact pressure p = {p:.2f}")
    print(f"total contact force {total:.2f}, p × quarter arc {expected:.2f}:"
          f" {100 * error:+.2f} %")
    print(f"lumped pressure at the {len(inner)} inner nodes of Γc: "
          f"{100 * inner.min():+.2f} % … {100 * inner.max():+.2f} % of p")
    ok = (summary["status"] == "converged" and in_contact.all()
          and abs(error) <= TOLERANCE)
    print("agrees with Lamé to 1 %" if ok else "DOES NOT agree with Lamé")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
