r"""Rank 0 drives, every rank computes: the command service of the engine.

Each collective step is a *command*: rank 0 sends its name and a small
payload to every rank (:meth:`Service.call`), every other rank waits idle
in :meth:`Service.serve` and runs the same handler, and large data travel
inside the handler by scatter and gather. A handler's exception on any
rank is raised on rank 0 as one :class:`EngineError` (or
:class:`EngineInputError` for bad input), so a fault never leaves a rank
blocked in a later collective; a rank that failed while the others are
stuck in one of PETSc's collective calls aborts them all after
:data:`ABORT_AFTER` s. ``stop`` ends the workers with rank 0's exit code.

Signals (:data:`STOP_SIGNALS`) never cut a command short: rank 0 holds
back one that arrives during a command until every rank has finished it,
and a worker reports its own to rank 0 instead of dying (``mpiexec``
would then kill the others at once); docs/mpi.md, "Stopping a run"."""

import signal
import sys
import threading
import time

from ..errors import ProblemError, SolverError

__all__ = ["EngineError", "EngineInputError", "Service", "command",
           "HANDLERS", "memory_mb", "STOP_SIGNALS"]

#: name -> handler(service, payload, local); filled by :func:`command`.
HANDLERS = {}

#: MPI tag of the commands; a waiting worker polls at most every POLL s.
TAG, POLL = 2020, 1e-3

#: Seconds a rank whose command failed waits for the others before it
#: aborts every rank (:meth:`Service._rendezvous`).
ABORT_AFTER = 60.0

#: The signals that stop a run (the command line's exit codes 130, 143,
#: 129); held back during a command (:class:`_HeldSignals`).
STOP_SIGNALS = tuple(getattr(signal, name) for name in (
    "SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


def memory_mb():
    """(resident, peak resident) memory of this process in MB: VmRSS and
    VmHWM of /proc/self/status (Linux), else the peak ``ru_maxrss``
    twice."""
    try:
        with open("/proc/self/status") as stream:
            fields = dict(line.split(":", 1) for line in stream)
        return tuple(round(int(fields[k].split()[0]) / 1024.0, 1)
                     for k in ("VmRSS", "VmHWM"))
    except (OSError, KeyError, ValueError):
        import resource

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        return peak, peak


class EngineError(RuntimeError):
    """A collective step failed on some rank (message names the rank)."""


class EngineInputError(EngineError, ProblemError):
    """A collective step found the input bad (a handler raised a
    :class:`~solver.errors.SolverError`, e.g. K not positive definite):
    the command line's one line and exit code 2, as the serial engine's."""


def command(name):
    """Register ``handler(service, payload, local)`` as command ``name``."""
    def register(handler):
        HANDLERS[name] = handler
        return handler
    return register


class _HeldSignals:
    """While active, :data:`STOP_SIGNALS` (not ignored) are recorded, not
    handled; :meth:`release` puts the handlers back and returns the first
    recorded (or None). Only in the main thread (Python's signal handlers)."""

    def __init__(self):
        self.received, self.saved = [], {}

    def hold(self):
        if threading.current_thread() is not threading.main_thread():
            return self
        for signum in STOP_SIGNALS:
            previous = signal.getsignal(signum)
            if previous is not signal.SIG_IGN and previous is not None:
                self.saved[signum] = signal.signal(signum, self._record)
        return self

    def _record(self, signum, frame):
        self.received.append(signum)

    def pop(self):
        """The first signal recorded since the last pop (or None)."""
        first = self.received[0] if self.received else None
        self.received.clear()
        return first

    def release(self):
        for signum, handler in self.saved.items():
            signal.signal(signum, handler)
        self.saved = {}
        return self.pop()


class Service:
    """The communicator, the objects the commands keep between calls
    (``objects``: name -> distributed matrix, KSP, ...), per-command
    ``timings`` (name -> [calls, wall s, CPU s on this rank]) and ``memory``
    after each stage (stage -> [MB resident, MB peak]; :meth:`mark` adds rank
    0's own stages)."""

    #: The process's service, once :func:`solver.mpi.engine.service` made
    #: it (with PETSc initialised and every command registered).
    current = None

    def __init__(self, comm=None):
        from mpi4py import MPI

        self.comm = comm or MPI.COMM_WORLD
        self.rank, self.size = self.comm.Get_rank(), self.comm.Get_size()
        self.objects, self.timings, self.memory = {}, {}, {}
        self._sync = None
        self._signals = _HeldSignals()  # a worker's, held while it serves
        self._reported = None  # a stop signal a worker reported to rank 0

    def mark(self, stage):
        """Record this rank's memory after ``stage`` (:attr:`memory`)."""
        self.memory[stage] = list(memory_mb())

    @property
    def root(self):
        return self.rank == 0

    def call(self, name, payload=None, local=None):
        """(rank 0) Run command ``name`` on every rank, rank 0's handler also
        given its large data ``local``; rank 0's result, or
        :class:`EngineError` if any rank failed. A stop signal during the
        command reaches rank 0's handler once the command has ended on every
        rank."""
        held = _HeldSignals().hold()
        try:
            self._send((name, payload))
            return self._run(name, payload, local)
        finally:
            signum = held.release()
            signum = signum or self._reported
            self._reported = None
            if signum is not None:
                signal.raise_signal(signum)

    def _send(self, message):
        """Rank 0's command to every worker (point to point, tag
        :data:`TAG`; few ranks)."""
        for rank in range(1, self.size):
            self.comm.send(message, dest=rank, tag=TAG)

    def _receive(self):
        """A worker's next command, waited for *idle* (short sleeps, not a
        blocking MPI call, which busy-waits and would take a core from rank 0's
        serial work)."""
        wait = 1e-5
        while not self.comm.iprobe(source=0, tag=TAG):
            time.sleep(wait)
            wait = min(2 * wait, POLL)
        return self.comm.recv(source=0, tag=TAG)

    def _run(self, name, payload, local):
        clock, cpu = time.perf_counter(), time.process_time()
        try:
            out, error = HANDLERS[name](self, payload, local), None
        except SolverError as exc:  # bad input: its own message
            out, error = None, (True, str(exc))
        except Exception as exc:  # noqa: BLE001 - reported collectively
            out, error = None, (False, f"{type(exc).__name__}: {exc}")
        entry = self.timings.setdefault(name, [0, 0.0, 0.0])
        entry[0] += 1
        entry[1] += time.perf_counter() - clock
        entry[2] += time.process_time() - cpu
        self.mark(name)
        self._rendezvous(name, error)
        statuses = self.comm.gather((error, self._signals.pop()), root=0)
        if self.root:
            errors = [e for e, _ in statuses]
            self._reported = next((s for _, s in statuses if s), None)
            failed = [(r, e) for r, e in enumerate(errors) if e]
            if failed:
                rank, (bad_input, text) = failed[0]
                if bad_input:
                    raise EngineInputError(text)
                raise EngineError(f"{name} failed on rank {rank} of "
                                  f"{self.size}: {' '.join(text.split())}")
        return out

    def _rendezvous(self, name, error):
        """Wait, idle, until every rank has finished command ``name``. A rank
        whose handler failed may have left the others in one of PETSc's
        collective calls: after :data:`ABORT_AFTER` s it prints its error on
        one line and aborts the communicator (no hang)."""
        if self.size == 1:
            return
        if self._sync is None:  # its own communicator: a barrier must not
            self._sync = self.comm.Dup()  # match a collective left waiting
        request = self._sync.Ibarrier()
        deadline = time.monotonic() + ABORT_AFTER
        wait = 1e-5
        while not request.Test():
            if error is not None and time.monotonic() > deadline:
                text = " ".join(error[1].split())
                print(f"error: {name} failed on rank {self.rank} of "
                      f"{self.size} while the others were still in a "
                      f"collective call: {text} (aborting all ranks)",
                      file=sys.stderr, flush=True)
                self.comm.Abort(1)
            time.sleep(wait)
            wait = min(2 * wait, POLL)

    def serve(self):
        """(ranks > 0) Run commands until ``stop``; return its exit code.
        A stop signal meanwhile is reported to rank 0 with the current or
        next command (rank 0 decides), not acted on here."""
        self._signals.hold()
        try:
            while True:
                name, payload = self._receive()
                if name == "stop":
                    return int(payload)
                self._run(name, payload, None)
        except BaseException as exc:  # lost rank 0: do not hang
            print(f"error: rank {self.rank}: {' '.join(str(exc).split())}",
                  file=sys.stderr)
            self.comm.Abort(1)
            raise
        finally:
            self._signals.release()

    def stop(self, code):
        """(rank 0) End the workers with exit code ``code``."""
        self._send(("stop", int(code)))

    def gather_stats(self):
        """Per-rank counts and timings, gathered (rank 0: list by rank)."""
        import resource

        usage = resource.getrusage(resource.RUSAGE_SELF)
        stats = dict(rank=self.rank, peak_rss_mb=usage.ru_maxrss / 1024.0,
                     cpu_s=round(usage.ru_utime + usage.ru_stime, 3),
            seconds={k: round(v[1], 4) for k, v in self.timings.items()},
            cpu_seconds={k: round(v[2], 4) for k, v in self.timings.items()},
            calls={k: v[0] for k, v in self.timings.items()},
            memory_mb=dict(self.memory))
        stats.update(self.objects.get("counts", {}))
        return self.comm.gather(stats, root=0)


@command("stats")
def _stats(service, payload, local):
    return service.gather_stats()
