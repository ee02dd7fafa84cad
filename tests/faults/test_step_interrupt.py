"""A friction run interrupted between writing a step's VTK file and
counting the step (solver/output/stepfiles.py).

Found by tests/faults/test_runs.py::test_interrupted_friction_run once in
a full run: SIGTERM landed after ``steps/step_0012.vtu`` had been renamed
into place but before the writer counted step 12, so the folder held 12
step files, ``result.npz`` and the summary 11. The signal is made
deterministic here: the atomic write completes, then KeyboardInterrupt
(what the runner's handler raises) comes before the count. The folder must
then list exactly the counted steps, in the files, ``result.pvd`` and
the summary's ``files``.
"""

import contextlib
import os

import numpy as np
import pytest

from solver import load_problem, solve_friction
from solver.output import stepfiles
from solver.output.folder import OutputFolder


@pytest.fixture(scope="module")
def steps(exported):
    problem = load_problem(exported(118)[0])
    fields = []
    solve_friction(problem, 0.3, steps=3, formulation="projection",
                   on_step=lambda f: fields.append(dict(f)))
    return problem, fields


def test_interrupt_after_the_file_before_the_count(steps, tmp_path,
                                                   monkeypatch):
    problem, fields = steps
    assert len(fields) == 3
    folder = OutputFolder(tmp_path / "out")
    writer = stepfiles.StepWriter(folder, problem, len(fields))
    writer(fields[0])
    writer(fields[1])
    real = stepfiles.atomic_path

    @contextlib.contextmanager
    def interrupted_after(path):
        with real(path) as tmp:
            yield tmp
        raise KeyboardInterrupt  # the file is in place, not yet counted

    monkeypatch.setattr(stepfiles, "atomic_path", interrupted_after)
    with pytest.raises(KeyboardInterrupt):
        writer(fields[2])
    monkeypatch.setattr(stepfiles, "atomic_path", real)
    assert writer.count == 2
    listed = sorted(os.listdir(tmp_path / "out" / "steps"))
    assert listed == ["step_0001.vtu", "step_0002.vtu"]
    assert [name for name in folder.files if name.startswith("steps")] == \
        [os.path.join("steps", n) for n in listed]
    writer.finish({})
    with np.load(tmp_path / "out" / "result.npz") as npz:
        assert npz["displacement"].shape[0] == 2
        np.testing.assert_array_equal(npz["displacement"][1],
                                      fields[1]["displacement"])
    pvd = (tmp_path / "out" / "result.pvd").read_text()
    assert "step_0002.vtu" in pvd and "step_0003.vtu" not in pvd
    folder.release()
