r"""
The thesis's §6 two-DOF bar system (Fig. 17) as a problem file.

This system has no mesh, so SfePy has nothing to assemble: the script writes
the thesis's numbers directly through the same ``.npz`` format
(``kind = "discrete"``), so that both thesis examples go through the same
solver::

    K = 1e4 * diag(9, 9),   f = [1000, -1000]^T,
    contact node A with DOFs (u_x, u_y), gap s = 0.005 along nu = (0, -1).

The lost Fig. 17 is reconstructed with the obstacle below A (nu = (0, -1)):
the load then closes the gap at load step 45 of 100. See
:func:`solver.examples.two_dof_bar`.

Usage examples::

  python sfepy_problems/two_dof_bar.py output/two_dof_bar.npz
  python -m solver output/two_dof_bar.npz --info
"""
import os
import sys

from solver.examples import two_dof_bar
from solver.problem import save_problem


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or argv[0].startswith("-"):
        print("usage: python sfepy_problems/two_dof_bar.py OUTPUT.npz",
              file=sys.stderr)
        return 2
    try:
        os.makedirs(os.path.dirname(os.path.abspath(argv[0])), exist_ok=True)
        save_problem(argv[0], two_dof_bar())
    except OSError as exc:
        print(f"error: cannot write {argv[0]}: {exc.strerror}",
              file=sys.stderr)
        return 2
    print(f"wrote {argv[0]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
