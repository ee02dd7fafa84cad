"""Completed load steps of a friction run, delivered in order.

On the condensed system a step is solved on Γc only; its displacement in
all unknowns is recovered later, for up to :data:`BATCH` steps in one
solve with many right-hand sides. The :class:`StepStream` then passes each
step, complete, to the caller's ``on_step`` and keeps it in memory only if
asked, so that a long run can be written to disk in bounded memory.

Kept without an ``on_step`` on the condensed system, the steps' fields in
all unknowns (``u``, ``displacement``) are recovered only when first read
(:class:`~solver.contact.result.Deferred`): every step is fully
determined by its Γc unknowns and w = K⁻¹f, and those back-substitutions
in all unknowns cost more than the Newton iterations on Γc, for a history
the caller may never read (the contact fields of every step are kept as
they come)."""

import numpy as np

from ..result import Deferred

__all__ = ["StepStream", "STEP_FIELDS", "MAX_LOAD_STEPS", "BATCH"]

#: Per-step arrays of a friction result, in the order they are stored.
STEP_FIELDS = ("load_factor", "stage", "u", "displacement", "contact_force",
               "contact_pressure", "contact_pressure_consistent",
               "friction_traction", "friction_bound",
               "tangential_displacement", "in_contact", "stick", "slip")

#: The per-step fields over Γc, kept as the steps come.
CONTACT_FIELDS = tuple(key for key in STEP_FIELDS
                       if key not in ("u", "displacement"))

#: The per-step fields in all unknowns, recovered when first read.
RECOVERED = ("u", "displacement")

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
        # kept and condensed, no caller to serve: u, displacement on demand
        self.deferred = [] if (keep and on_step is None
                               and space.condensed) else None

    def add(self, fields, u, w, prescribed):
        """A converged step: its Γc fields, u (reduced, or on Γc with ``w`` =
        K⁻¹f of the step when the reduction ``space`` is condensed) and its
        Dirichlet values."""
        if self.deferred is not None:
            self.deferred.append((np.array(u, copy=True), w, prescribed))
            self._keep(fields, CONTACT_FIELDS)
            self.count += 1
            return
        self.pending.append((fields, np.array(u, copy=True), w, prescribed))
        if not self.space.condensed or len(self.pending) >= BATCH:
            self.flush()

    def flush(self):
        """Recover and deliver every pending step."""
        pending, self.pending = self.pending, []
        if not pending:
            return
        if not self.space.condensed:  # u = y (or W y: a floating body)
            columns = [self.space.displacement(entry[1])
                       for entry in pending]
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

    def _keep(self, fields, keys=STEP_FIELDS):
        """Store step ``count``'s fields in the preallocated arrays."""
        k = self.count
        for key in keys:
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
        arrays = {key: array[:self.count]
                  for key, array in self.kept.items()}
        if self.deferred is not None:
            recovery = Deferred(self._recover, RECOVERED)
            arrays.update({key: recovery for key in RECOVERED})
        return arrays

    def _recover(self):
        """``u`` and ``displacement`` of every kept step, in batches of
        :data:`BATCH` back-substitutions (then the inputs are dropped)."""
        steps, self.deferred = self.deferred, []
        problem, count = self.problem, len(steps)
        u = np.empty((count, problem.n_dofs))
        mesh = problem.kind == "mesh"
        for start in range(0, count, BATCH):
            batch = steps[start:start + BATCH]
            u[start:start + len(batch)] = self.space.displacement(
                np.column_stack([entry[0] for entry in batch]),
                np.column_stack([entry[1] for entry in batch])).T
            steps[start:start + BATCH] = [(None, None, entry[2])
                                          for entry in batch]  # w freed
        if not mesh:
            return dict(u=u, displacement=u[:, problem.contact_dofs])
        displacement = np.empty((count,) + problem.u_prescribed.shape)
        for k, (_, _, prescribed) in enumerate(steps):
            displacement[k] = problem.u_prescribed if prescribed is None \
                else prescribed
        rows, columns = problem.dof_map[:, 0], problem.dof_map[:, 1]
        displacement[:, rows, columns] = u
        return dict(u=u, displacement=displacement)
