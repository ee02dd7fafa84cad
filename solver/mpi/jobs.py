"""The command line's solve calls on the petsc engine: the serial jobs of
:mod:`solver.cli.jobs` call these in place of :func:`solver.contact.
solve_frictionless` and :func:`solver.contact.solve_friction` (same keyword
arguments; ``--system``, ``--start`` and ``--ksp`` translated)."""

import functools

from ..errors import SolverError

__all__ = ["solvers"]


def solvers(args):
    """(solve_frictionless, solve_friction) for the parsed ``args``."""
    from .friction import solve_friction
    from .frictionless import solve_frictionless

    return (functools.partial(_frictionless, solve_frictionless, args),
            functools.partial(_friction, solve_friction))


def _frictionless(solve, args, problem, condense=None, start=None,
                  backend="auto", **options):
    if start == "nested":
        raise SolverError("--start nested runs on the serial engine; the "
                          "petsc engine starts from λ = 0 (--start free)")
    system = "full" if condense is False else "condensed"
    return solve(problem, system=system, ksp=args.ksp, **options)


def _friction(solve, problem, friction, condense=None, backend="auto",
              **options):
    if condense is False:
        raise SolverError("--system full with friction runs on the serial "
                          "engine")
    return solve(problem, friction, **options)
