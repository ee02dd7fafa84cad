"""The ranks of an ``mpiexec`` launch seen from /proc, and the files of an
output folder: shared by the signal tests of the petsc engine
(test_mpi_signals.py) and of the partitioned run
(faults/test_fault_partitioned.py)."""

import os
import signal


def _children(launcher):
    """(pid, /proc/pid's status fields, environment) of every child of
    ``launcher``."""
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as stream:
                parent = int(stream.read().rsplit(")", 1)[1].split()[1])
            if parent != launcher:
                continue
            with open(f"/proc/{entry}/status") as stream:
                fields = dict(line.split(":", 1) for line in stream)
            with open(f"/proc/{entry}/environ", "rb") as stream:
                env = stream.read().split(b"\0")
        except (OSError, ValueError, IndexError):
            continue
        yield int(entry), fields, env


def rank_pid(launcher, rank):
    """The process id of ``rank`` among the children of ``launcher``."""
    for pid, _, env in _children(launcher):
        if f"OMPI_COMM_WORLD_RANK={rank}".encode() in env:
            return pid
    raise AssertionError(f"rank {rank} of mpiexec {launcher} not found")


def ranks_catch_sigterm(launcher, ranks=2):
    """Whether every child of ``launcher`` (the ranks) handles SIGTERM
    (its SigCgt mask): a worker does once it serves; before, mpiexec's
    SIGTERM would kill it as any process starting up."""
    found = [int(fields["SigCgt"], 16) >> (signal.SIGTERM - 1) & 1
             for _, fields, _ in _children(launcher)]
    return len(found) == ranks and all(found)


def files(folder):
    """The files under ``folder``, relative to it, sorted."""
    return sorted(os.path.relpath(os.path.join(d, f), folder)
                  for d, _, names in os.walk(folder) for f in names)
