"""Completed load steps of a friction run, delivered in order.

On the condensed system a step is solved on Γc only; its displacement in
all unknowns is recovered later, for up to :data:`BATCH` steps in one
solve with many right-hand sides. The :class:`StepStream` then passes each
step, complete, to the caller's ``on_step`` and keeps it in memory only if
asked, so that a long run can be written to disk in bounded memory."""

import numpy as np

__all__ = ["StepStream", "STEP_FIELDS", "MAX_LOAD_STEPS", "BATCH"]

#: Per-step arrays of a friction result, in the order they are stored.
STEP_FIELDS = ("load_factor", "stage", "u", "displacement", "contact_force",
               "contact_pressure", "contact_pressure_consistent",
               "friction_traction", "friction_bound",
               "tangential_displacement", "in_contact", "stick", "slip")

#: Largest number of load steps a run accepts (the thesis uses 100).
MAX_LOAD_STEPS = 100_000

#: Condensed steps whose displacements are recovered in one solve.
BATCH = 32

#: Steps for which the kept arrays are allocated at first (then doubled):
#: for up to this many steps they are filled in place, never copied.
CAPACITY = 1024


class StepStream:
    """Collects completed steps, recovers their displacements and delivers
    them, in order, to ``on_step`` (and to :meth:`arrays` if ``keep``)."""

    def __init__(self, problem, space, on_step=None, keep=True,
                 total=None):
        self.problem, self.space = problem, space
        self.on_step, self.keep = on_step, keep
        self.pending, self.count = [], 0
        self.total = total  # number of steps of the run, if known
        self.kept = {}  # key -> (capacity, ...) array, rows < count filled

    def add(self, fields, u, w, prescribed):
        """A converged step: its Γc fields, u (reduced, or on Γc with ``w`` =
        K⁻¹f of the step when the reduction ``space`` is condensed) and its
        Dirichlet values."""
        self.pending.append((fields, np.array(u, copy=True), w, prescribed))
        if not self.space.condensed or len(self.pending) >= BATCH:
            self.flush()

    def flush(self):
        """Recover and deliver every pending step."""
        pending, self.pending = self.pending, []
        if not pending:
            return
        if not self.space.condensed:
            columns = [entry[1] for entry in pending]
        else:
            U = self.space.displacement(
                np.column_stack([entry[1] for entry in pending]),
                np.column_stack([entry[2] for entry in pending]))
            columns = list(U.T)
        problem = self.problem
        for (fields, _, _, prescribed), u in zip(pending, columns):
            fields["u"] = u
            fields["displacement"] = (
                problem.full_displacement(u, prescribed)
                if problem.kind == "mesh" else u[problem.contact_dofs])
            if self.keep:
                self._keep(fields)
            self.count += 1
            if self.on_step is not None:
                self.on_step(fields)

    def _keep(self, fields):
        """Store step ``count``'s fields in the preallocated arrays."""
        k = self.count
        for key in STEP_FIELDS:
            value = np.asarray(fields[key])
            array = self.kept.get(key)
            if array is None or k >= len(array):
                size = CAPACITY if array is None else 2 * len(array)
                if self.total is not None:
                    size = max(min(size, self.total), k + 1)
                grown = np.empty((size,) + value.shape, value.dtype)
                if array is not None:
                    grown[:k] = array[:k]
                array = self.kept[key] = grown
            array[k] = value

    def arrays(self):
        """The kept steps as arrays (first axis = step); {} if not kept."""
        if not self.keep:
            return {}
        if not self.kept:  # no step completed
            return {key: np.array([]) for key in STEP_FIELDS}
        return {key: array[:self.count] for key, array in self.kept.items()}
