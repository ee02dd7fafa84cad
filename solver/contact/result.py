"""The result objects of the contact solvers: ``OptimizeResult``s (a dict
with attribute access, as every SciPy solver returns) with a short repr
that names what was solved and how it ended, never the arrays."""

import numpy as np
from scipy.optimize import OptimizeResult

__all__ = ["ContactResult", "FrictionResult"]


def _counts(result):
    return (f"nit={result.get('nit')}, njev={result.get('njev')}, "
            f"nfev={result.get('nfev')}")


class ContactResult(OptimizeResult):
    """Result of :func:`solver.contact.solve_frictionless`."""

    def __repr__(self):
        n = self.get("in_contact")
        contact = "?" if n is None else f"{int(np.sum(n))}/{len(n)}"
        return (f"<ContactResult {self.get('method')} method, "
                f"{'converged' if self.get('success') else 'NOT converged'}"
                f" (status {self.get('status')}), {_counts(self)}, "
                f"{contact} contact nodes in contact, "
                f"{'condensed' if self.get('condensed') else 'full'} system>")

    __str__ = __repr__


class FrictionResult(OptimizeResult):
    """Result of :func:`solver.contact.solve_friction`."""

    def __repr__(self):
        return (f"<FrictionResult f_c={self.get('friction')}, "
                f"{self.get('formulation')} formulation, "
                f"{self.get('coulomb')} bound, {self.get('method')} method, "
                f"{self.get('steps_completed')}/{self.get('steps')} steps, "
                f"{'converged' if self.get('success') else 'NOT converged'}"
                f", {_counts(self)}>")

    __str__ = __repr__
