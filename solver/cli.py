"""Command line interface: ``python -m solver PROBLEM.npz [options]``.

A thin layer over the library: it parses arguments, calls the public API and
prints. Errors caused by the input end with a one-line message on stderr and
exit code 2 (``--debug`` shows the traceback instead).

Exit codes: 0 success, 2 bad input or usage.
"""

import argparse
import json
import sys
import traceback

from . import __version__
from .errors import SolverError
from .problem import FORMAT_VERSION, load_problem

EXIT_OK, EXIT_INPUT = 0, 2


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse's own code)
        self.exit(EXIT_INPUT, f"{self.prog}: error: {message}\n")


def build_parser():
    parser = _Parser(
        prog="python -m solver",
        description="Contact of an elastic body with a rigid obstacle "
                    "(semismooth Newton). Reads a problem file written by "
                    "sfepy_problems/*.py (format version "
                    f"{FORMAT_VERSION}).")
    parser.add_argument("problem", help="problem file (.npz)")
    parser.add_argument("--info", action="store_true",
                        help="load and validate the problem, print a "
                             "summary and stop")
    parser.add_argument("--json", action="store_true",
                        help="with --info: print the summary as JSON")
    parser.add_argument("--debug", action="store_true",
                        help="show tracebacks of errors")
    parser.add_argument("--version", action="version",
                        version=f"%(prog)s {__version__}")
    return parser


def format_summary(info):
    """The ``--info`` summary as readable lines."""
    meta = info["meta"]
    lines = [f"problem kind      {info['kind']}",
             f"reduced DOFs      {info['dofs']}",
             f"contact nodes Nc  {info['contact_nodes']} "
             f"({info['contact_nodes_free']} free, "
             f"{info['contact_nodes'] - info['contact_nodes_free']} "
             "supported)",
             f"K                 nnz {info['K_nnz']}, "
             f"‖K‖_F = {info['K_norm_fro']:.6g}, "
             f"max |K_ij| = {info['K_norm_max']:.6g}",
             f"‖f‖               {info['f_norm']:.6g}",
             f"sum of M          {info['M_sum']:.12g}"]
    if info["kind"] == "mesh":
        x, y = info["obstacle"]
        rng = info["obstacle_t_range"]
        lines += [f"mesh              {meta.get('mesh')}: "
                  f"{info['triangles']} triangles, {info['nodes']} nodes",
                  f"material          E = {meta['E']:g}, nu = {meta['nu']:g},"
                  f" plane {meta['plane']}",
                  f"obstacle          x(t) = {x}, y(t) = {y}"
                  + ("" if rng is None else f", t in [{rng[0]}, {rng[1]}]")]
    else:
        lines += [f"description       {meta['description']}",
                  f"gaps s            {info['gap']}",
                  f"normals           {info['normal']}"]
    if "load" in meta:
        lines.append(f"load              {json.dumps(meta['load'])}")
    return "\n".join(lines)


def main(argv=None):
    """Run the command line; return the exit code."""
    args = build_parser().parse_args(argv)
    try:
        problem = load_problem(args.problem)
        if args.info:
            info = problem.summary()
            print(json.dumps(info, indent=2) if args.json
                  else format_summary(info))
            return EXIT_OK
        print(format_summary(problem.summary()))
        print("(solving is not implemented yet: only --info is available)",
              file=sys.stderr)
        return EXIT_INPUT
    except SolverError as exc:
        if args.debug:
            traceback.print_exc()
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_INPUT
