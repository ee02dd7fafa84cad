"""The result of every contact solve, whatever the case and method
(scipy.optimize's rule): an ``OptimizeResult`` (a dict with attribute
access) whose short repr names what was solved and how it ended, never
the arrays. Its fields are listed in docs/results.md; ``list(result)``
shows the keys."""

import numpy as np
from scipy.optimize import OptimizeResult

__all__ = ["ContactResult"]


def _counts(result):
    return (f"nit={result.get('nit')}, njev={result.get('njev')}, "
            f"nfev={result.get('nfev')}")


class ContactResult(OptimizeResult):
    """Result of :func:`solver.solve` (every case)."""

    def __repr__(self):
        state = "converged" if self.get("success") else "NOT converged"
        if self.get("friction") is not None:
            return (f"<ContactResult f_c={self.get('friction')}, "
                    f"{self.get('formulation')} formulation, "
                    f"{self.get('coulomb')} bound, {self.get('method')} "
                    f"method, {self.get('steps_completed')}/"
                    f"{self.get('steps')} steps, {state}, {_counts(self)}>")
        n = self.get("in_contact")
        contact = "?" if n is None else f"{int(np.sum(n))}/{len(n)}"
        return (f"<ContactResult {self.get('method')} method, {state}"
                f" (status {self.get('status')}), {_counts(self)}, "
                f"{contact} contact nodes in contact, "
                f"{'condensed' if self.get('condensed') else 'full'} system>")

    __str__ = __repr__
