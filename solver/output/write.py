"""Everything a solve leaves in its output folder, for every case (one
body or two, discrete, 2D and 3D): :func:`write_all` writes the outputs of
a finished solve and returns the ``summary.json`` dictionary; a friction
run streams its steps to disk as they complete (:class:`StepOutputs`),
and an interrupted one still leaves them readable."""

import os

import numpy as np

from .files import (frames_on_contact, friction_summary_of, summary_of,
                    write_result)
from .stepfiles import StepWriter
from .vtk import write_vtk

__all__ = ["StepOutputs", "write_all", "interface_summary"]


class StepOutputs:
    """The completed steps of a friction run streamed into ``folder``
    (:class:`~solver.output.stepfiles.StepWriter`), as the run's ``on_step``;
    :meth:`finish` writes ``result.npz`` and ``result.pvd``, also after an
    interrupt. With the run's ``geometry`` a 3D run's step files hold the
    friction traction as a 3-vector."""

    def __init__(self, folder, problem, total_steps, geometry=None):
        self.folder, self.problem = folder, problem
        tangents = None if geometry is None else \
            frames_on_contact(problem, geometry)[2]
        self.writer = StepWriter(folder, problem, total_steps,
                                 tangents=tangents)

    def __call__(self, fields):
        self.writer(fields)

    @property
    def count(self):
        """Steps written so far."""
        return self.writer.count

    def finish(self, geometry, result=None):
        """``result.npz`` and ``result.pvd`` of the completed steps, with
        the per-node gaps, normals and tangent frames of ``geometry`` over
        Γc (:func:`~solver.output.files.frames_on_contact`) and, when the
        run ended (``result``), its per-step counts and verdict."""
        writer, problem = self.writer, self.problem
        nc = problem.n_contact
        gap, normal, tangents = frames_on_contact(problem, geometry)
        records = [] if result is None else result.records
        extra = dict(
            contact_nodes=(problem.contact_nodes if problem.kind == "mesh"
                           else np.arange(nc)),
            gap=gap, normal=normal, tangents=tangents,
            step_njev=np.array([r["njev"] for r in records[:writer.count]],
                               dtype=np.int64),
            step_nfev=np.array([r["nfev"] for r in records[:writer.count]],
                               dtype=np.int64),
            converged=np.array(result is not None and bool(result.success)),
            steps_completed=np.array(writer.count))
        if result is not None and problem.is_mortar:
            extra.update(mortar_D=result.mortar_D, covered=result.covered,
                         weighted_gap=result.weighted_gap, body=result.body)
        if writer.count == 0:
            writer.close()
            return
        writer.finish(extra)


def write_all(folder, problem, result, plots=False, tol=None,
              max_iter=None):
    """Write the outputs of a finished solve into ``folder`` (an
    :class:`~solver.output.folder.OutputFolder`; a friction run's steps
    are already there, :class:`StepOutputs`) and return the
    ``summary.json`` dictionary (written by the caller, last)."""
    friction = result.get("friction") is not None
    if friction:
        summary = friction_summary_of(result, problem, tol=tol,
                                      max_iter=max_iter)
    else:
        summary = summary_of(result, problem, tol=tol, max_iter=max_iter)
    if "engine" in result:
        summary["engine"] = result["engine"]
    if problem.is_mortar:
        summary.update(interface_summary(
            problem, _with_saved_pressure(folder, result) if friction
            else result))
    if not friction:
        if problem.is_mortar:
            from .two_body import write_two_body_result

            write_two_body_result(folder.file("result.npz"), result, problem)
        else:
            write_result(folder.file("result.npz"), result, problem)
    if problem.kind == "mesh" and (not friction or result.steps_completed):
        if problem.is_mortar:
            from .two_body import write_two_body_vtk

            if not friction:
                write_two_body_vtk(folder.file("result.vtu"), result,
                                   problem)
        elif not friction:
            write_vtk(folder.file("result.vtu"), result, problem)
    if plots and (not friction or result.steps_completed):
        for path in _figures(folder, problem, result).values():
            folder.file(os.path.basename(path))
    return summary


def _figures(folder, problem, result):
    """``--plots``: the thesis's figures in 2D, friction's per-step
    figures, the two bodies' interface; in 3D the convergence and the
    pressure against the radius (with Hertz's profile where the problem
    allows one, :func:`~solver.output.hertz_reference.hertz_reference`)."""
    if result.get("friction") is not None and not problem.is_mortar:
        from .friction_figures import write_friction_figures

        return write_friction_figures(folder.path, problem,
                                      _saved_steps(folder, result))
    if problem.is_mortar:
        from .two_body import write_two_body_figures
        from .two_body3d import write_two_body_figures3d

        if result.get("friction") is not None:
            result = _saved_steps(folder, result)
        write = write_two_body_figures if problem.dim == 2 \
            else write_two_body_figures3d
        return write(folder.path, problem, result)
    if problem.dim == 2:
        from .figures import write_figures

        return write_figures(folder.path, problem, result)
    from .figures3d import write_figures3d

    return write_figures3d(folder.path, problem, result)


def _saved_steps(folder, result):
    """The written result.npz with the run's settings, for the figures of
    a friction run (its steps were streamed to disk)."""
    from scipy.optimize import OptimizeResult

    with np.load(os.path.join(folder.path, "result.npz")) as data:
        steps = OptimizeResult({key: data[key] for key in data.files})
    steps.update({key: result[key] for key in (
        "steps", "friction", "formulation", "coulomb", "method",
        "steps_completed", "records") if key in result})
    for key in ("covered", "variant", "mortar_D", "body"):
        if key in result:
            steps[key] = result[key]
    return steps


def _with_saved_pressure(folder, result):
    """A friction result whose steps went to disk (the command line keeps
    none in memory) with its contact pressures read back from
    ``result.npz`` (and their patch recovery, two bodies), for
    :func:`interface_summary`."""
    if result.get("contact_pressure") is not None:
        return result
    path = os.path.join(folder.path, "result.npz")
    if not result.steps_completed or not os.path.exists(path):
        return result
    with np.load(path) as data:
        saved = {key: data[key] for key in ("contact_pressure",
                                            "contact_pressure_patch")
                 if key in data.files}
    from scipy.optimize import OptimizeResult

    return OptimizeResult(result, **saved)


def interface_summary(problem, result):
    """The interface's figures for summary.json (last step of friction)."""
    meta = problem.meta or {}
    D = np.asarray(result.mortar_D)
    summary = {"coupling": result.variant,
               "bodies": meta.get("bodies"),
               "slave_body": meta.get("slave_body"),
               "master_body": meta.get("master_body"),
               "slave_nodes": int(len(D)),
               "slave_nodes_covered": int(np.sum(result.covered))}
    pressure = result.get("contact_pressure")
    if pressure is not None and np.size(pressure):
        pressure = np.asarray(pressure)
        pressure = pressure[-1] if pressure.ndim == 2 else pressure
        summary.update(
            interface_normal_force=float(D @ pressure),
            max_interface_pressure=float(pressure.max(initial=0.0)))
    patch = result.get("contact_pressure_patch")
    if patch is not None and np.size(patch):
        patch = np.asarray(patch)
        patch = patch[-1] if patch.ndim == 2 else patch
        summary["max_interface_pressure_patch"] = float(
            patch.max(initial=0.0))
    return summary
