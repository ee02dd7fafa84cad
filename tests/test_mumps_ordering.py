"""benchmarks/mumps_ordering/run.py (the experiment behind
benchmarks/README.md's "A METIS ordering for MUMPS") still runs: its hook
compiles against the installed PETSc, MUMPS reports "Ordering given is
used" for the METIS rows (the script exits non-zero otherwise), and every
row's u agrees with the first AMD run on 1 rank (MUMPS's own ordering, an
independent factorisation) to 1e-8 on 1 and 2 ranks."""

import ctypes
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT
from solver.mpi import missing

REASON = missing() or next((f"{tool} not found: apt-get install petsc-dev "
                            "mpi-default-bin (docs/mpi.md)" for tool in
                            ("mpiexec", "mpicc", "gcc")
                            if shutil.which(tool) is None), None)
if REASON is None:
    try:
        ctypes.CDLL("libmetis.so.5")
    except OSError:
        REASON = "libmetis.so.5 not found: apt-get install libmetis5"
pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))


def test_metis_ordering_gives_the_same_answer(exported):
    path, _, _ = exported(1878)
    done = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "mumps_ordering" /
                             "run.py"), str(path), "--rounds", "1"],
        capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    rows = [line.split() for line in done.stdout.splitlines()[1:]]
    assert [(r[1], r[2]) for r in rows] == [("amd", "1"), ("amd", "2"),
                                            ("metis", "1"), ("metis", "2")]
    for row in rows:
        assert float(row[-1]) <= 1e-8, row
        assert int(row[7].replace(",", "")) > 0  # INFOG(29) was read
