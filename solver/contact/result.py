"""The result of every contact solve, whatever the case and method
(scipy.optimize's rule): an ``OptimizeResult`` (a dict with attribute
access) whose short repr names what was solved and how it ended, never
the arrays. Its fields are listed in docs/results.md; ``list(result)``
shows the keys.

A field may be :class:`Deferred`: computed on its first read, by any
access (``result.u``, ``result["u"]``, ``get``, ``items``, ``dict(result)``,
pickling), and stored in place of the placeholder. A friction run keeps its
steps' displacements in all unknowns that way (:mod:`~solver.contact.
friction.stream`)."""

import numpy as np
from scipy.optimize import OptimizeResult

__all__ = ["ContactResult", "Deferred"]


class Deferred:
    """Placeholder of the fields ``keys`` of a :class:`ContactResult`,
    which ``compute()`` returns together as a dict on the first read of any
    of them."""

    def __init__(self, compute, keys):
        self.compute, self.keys = compute, tuple(keys)

    def __repr__(self):
        return f"<computed on first read: {', '.join(self.keys)}>"


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

    def __getitem__(self, key):
        value = dict.__getitem__(self, key)
        if isinstance(value, Deferred):
            computed = value.compute()
            for name in value.keys:
                dict.__setitem__(self, name, computed[name])
            value = computed[key]
        return value

    def get(self, key, default=None):
        return self[key] if key in self else default

    def __iter__(self):  # dict(result), {**result}: keys, then self[key]
        return iter(dict.keys(self))

    def items(self):
        return [(key, self[key]) for key in self.keys()]

    def values(self):
        return [self[key] for key in self.keys()]

    def copy(self):
        return type(self)(self.items())

    def __reduce__(self):  # pickle and copy the computed fields
        return type(self), (self.items(),)
