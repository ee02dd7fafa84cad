r"""What :func:`solver.solve` accepts where: the cases, the options and the
rules that refuse a combination. One table, three readers: the front
checks every call against it (an option that does not apply is an error,
never silently ignored), :func:`support_table` prints the README's "What
works where" from it, and ``tests/test_combinations.py`` enumerates it.

A *case*: the dimension (2, 3), the bodies ("rigid": one body against a
rigid obstacle, "two-body": two elastic bodies by dual mortar,
"discrete": gaps and normals given, no mesh, "partitioned": the folder
of ``python -m solver convert``, read in parts by the ranks of
``mpiexec``), the contact ("frictionless",
"friction") and the engine ("serial", "petsc")."""

from dataclasses import dataclass

import numpy as np

from ..contact import COULOMB, FORMULATIONS, GAP_MODES, default_method
from ..errors import SolverError
from ..linalg import BACKENDS, ITERATIVE

__all__ = ["Case", "Rule", "RULES", "AMG_REFUSALS", "PARTITIONED_RULES",
           "CONVERTED_RULES", "converted", "auto_eligible",
           "DEFAULTS", "METHODS", "SYSTEMS",
           "STARTS", "ENGINES", "KSPS", "VARIANTS", "case_of", "given_options",
           "resolve", "check_geometry_rules", "support_table"]

METHODS = ("min", "fb")
SYSTEMS = ("auto", "condensed", "full")
STARTS = ("nested", "free")
ENGINES = ("serial", "petsc")
KSPS = ("mumps", "gamg", "hypre")
VARIANTS = ("mortar", "node-to-segment")

#: Every option of :func:`solver.solve` and its default. An option counts
#: as *given* when it differs from its default.
DEFAULTS = dict(
    friction=None, method=None, system="auto", start=None, formulation=None,
    coulomb=None, steps=None, gap=None, backend="auto", engine=None,
    ksp=None, tol=1e-10, max_iter=100, gap_scale=None, search_interval=None,
    candidates=None, margin=None, rollers=None, x0=None, variant=None,
    options=None, geometry=None, progress=None, on_step=None,
    keep_steps=True)

#: Options of friction runs only, and of frictionless solves only.
FRICTION_ONLY = ("formulation", "coulomb", "steps", "progress", "on_step",
                 "keep_steps")
FRICTIONLESS_ONLY = ("start", "x0")


@dataclass(frozen=True)
class Case:
    """dim, bodies ("rigid", "two-body", "discrete", "partitioned"), contact
    ("frictionless", "friction") and engine ("serial", "petsc")."""

    dim: int
    bodies: str
    contact: str
    engine: str
    support: str = "supported"  # or "floating": K has rigid-body modes
    coupling: str = "none"  # "mortar": a folder of two bodies

    def __str__(self):
        held = ", held by contact only" if self.support == "floating" \
            else ""
        return (f"{self.dim}D, {self.bodies}{held}, {self.contact}, "
                f"{self.engine} engine")


def case_of(problem, friction, engine):
    """The :class:`Case` of a call."""
    bodies = ("two-body" if problem.is_mortar else
              "rigid" if problem.kind == "mesh" else
              "partitioned" if problem.kind == "partitioned" else "discrete")
    name = engine if isinstance(engine, str) or engine is None \
        else engine.name
    floating = bodies in ("rigid", "two-body") and problem.floating
    mortar = bodies == "partitioned" and bool(problem.meta.get("mortar"))
    return Case(problem.dim, bodies,
                "frictionless" if friction is None else "friction",
                name or "serial", "floating" if floating else "supported",
                "mortar" if mortar else "none")


def given_options(options):
    """The names of the options that differ from their defaults."""
    given = set()
    for name, value in options.items():
        default = DEFAULTS[name]
        if value is None and default is None:
            continue
        if isinstance(value, str) or value is None or isinstance(
                value, bool) or isinstance(default, (str, bool)):
            if value != default:
                given.add(name)
        else:
            given.add(name)
    return given


@dataclass(frozen=True)
class Rule:
    """A combination that is refused: ``option`` given (or resolved) where
    ``applies(case, settings)`` holds; ``where`` says it in words (the
    README's table), ``reason`` is the one-line error."""

    option: str
    where: str
    reason: str
    applies: object
    label: str = None  # the option (and value) as the README shows it

    def message(self, case, settings):
        """The error: the option, the case, the reason."""
        given = f"{self.option}={_shown(settings, self.option)}" \
            if self.option in settings and not (
                settings[self.option] is None and self.label) \
            else self.label  # engine=None: the label's engine='serial'
        return f"{given} is not supported for {case}: {self.reason}"


def _shown(settings, name):
    value = settings.get(name)
    return repr(value) if isinstance(value, str) or value is None \
        else type(value).__name__ if callable(value) else repr(value)


def _friction_only(name):
    return Rule(name, "frictionless solves",
                "it applies to friction runs (give friction=f_c)",
                lambda c, s, g: name in g and c.contact == "frictionless")


def _frictionless_only(name):
    return Rule(name, "friction runs",
                "it applies to frictionless solves (each load step starts "
                "from the previous one)",
                lambda c, s, g: name in g and c.contact == "friction")


def _amg(where, reason, applies):
    return Rule("backend", where, reason,
                lambda c, s, g: s["backend"] == "amg" and applies(c, s, g),
                "backend='amg'")


#: What the iterative path (backend="amg": the active set method, its
#: Newton systems by AMG-preconditioned CG) does not do yet.
AMG_REFUSALS = (
    ("friction with formulation='thesis'", "the active set method solves "
     "the projection formulation; use formulation='projection' (the "
     "default) or a factorisation",
     lambda c, s, g: c.contact == "friction"
     and s["formulation"] == "thesis"),
    ("discrete problems", "its near-null space is the rigid-body modes "
     "of meshed bodies (no mesh here)",
     lambda c, s, g: c.bodies not in ("rigid", "two-body")),
    ("system='condensed'", "it iterates on the full primal system; "
     "condensing onto Γc factorises K",
     lambda c, s, g: s["system"] == "condensed"),
    ("method='fb'", "the active set method is semismooth Newton with "
     "φ_min", lambda c, s, g: s["method"] != "min"),
    ("options", "they tune the damped Newton's line search; the active "
     "set method takes full steps", lambda c, s, g: "options" in g),
)


def _partitioned(option, reason, applies, label=None):
    return Rule(option, "a partitioned problem (a folder)", reason,
                lambda c, s, g: c.bodies == "partitioned"
                and applies(c, s, g),
                label)


_CONVERTED = ("the distributed solve runs with the gaps, nodes and "
              "rollers of the conversion, from the free start (friction: "
              "each load step from the previous one); run the .npz for it")

#: What the distributed solve of a partitioned problem does not do
#: (:mod:`solver.mpi.distributed`, :mod:`solver.mpi.partitioned_friction`;
#: the full system by Krylov, :mod:`solver.mpi.partitioned_full`): it runs
#: on the petsc engine, condensed, from the free start (friction: the
#: projection formulation on all of Γc), or frictionless on the full system
#: with ksp='gamg' / 'hypre' (φ_min), with the conversion's gaps.
PARTITIONED_RULES = (
    _partitioned("engine", "its K is read in parts by the ranks of "
                 "mpiexec: engine='petsc', under mpiexec -n N",
                 lambda c, s, g: c.engine != "petsc", "engine='serial'"),
    _partitioned("formulation", "the distributed friction runs the "
                 "projection formulation on Γc's Schur complement; the "
                 "thesis's split runs on the full system: run the .npz",
                 lambda c, s, g: c.contact == "friction"
                 and s["formulation"] == "thesis", "formulation='thesis'"),
    _partitioned("on_step", "the steps' u stay on the ranks; each step's "
                 "pieces are written to DIR/steps/ by the command line "
                 "(PartitionedPlan.run(outdir=DIR))",
                 lambda c, s, g: "on_step" in g),
    _partitioned("system", "on a folder the full system runs by Krylov, "
                 "ksp='gamg' or 'hypre' (no rank factorises the whole K); "
                 "without system='full' the system condensed onto Γc "
                 "(MUMPS's Schur complement)",
                 lambda c, s, g: s["system"] == "full"
                 and s["ksp"] not in ("gamg", "hypre"),
                 "system='full' without ksp='gamg' or 'hypre'"),
    _partitioned("ksp", "it chooses the Krylov preconditioner of the full "
                 "system (system='full'); the condensed system factorises "
                 "with MUMPS", lambda c, s, g: "ksp" in g
                 and s["system"] != "full", "ksp without system='full'"),
    Rule("system", "a partitioned problem of two bodies (a folder)",
         "the ranks solve the nodewise problem in v = Tu on the full system "
         "(K̂ = PᵀKP, P = T⁻¹Rᵀ): system='full' with ksp='gamg' or "
         "ksp='hypre', frictionless or with friction; the condensed path "
         "(MUMPS's Schur complement of K) does not take the coupling",
         lambda c, s, g: c.coupling == "mortar" and s["system"] != "full",
         "system (condensed) on two bodies"),
    _partitioned("method", "the full system of a folder runs φ_min (its "
                 "Newton decisions reduced over the ranks)",
                 lambda c, s, g: s["system"] == "full"
                 and s["method"] != "min", "method='fb' with system='full'"),
) + tuple(
    _partitioned(name, _CONVERTED, lambda c, s, g, name=name: name in g)
    for name in ("start", "gap", "search_interval", "gap_scale",
                 "candidates", "margin", "rollers", "x0",
                 "options", "geometry", "variant")) + (
    _partitioned("backend", "the distributed solve factorises with "
                 "MUMPS", lambda c, s, g: s["backend"] != "auto",
                 "backend"),)

def converted(case, settings):
    """Whether a call runs by conversion on the fly
    (:mod:`solver.mpi.on_the_fly`): friction on the full system of one
    supported body against a rigid obstacle (a ``.npz``) on the petsc
    engine; its folder then runs :mod:`solver.mpi.krylov_friction`."""
    return (case.engine == "petsc" and case.contact == "friction"
            and case.bodies == "rigid" and case.support == "supported"
            and not settings["condense"])


def _on_the_fly(option, reason, applies, label=None):
    return Rule(option, "friction on the petsc engine's full system from "
                "a .npz (converted on the fly)", reason,
                lambda c, s, g: converted(c, s) and applies(c, s, g), label)


_ON_THE_FLY = ("the .npz is converted on the fly to a partitioned folder "
               "(gaps by gap='obstacle' or 'body', roller nodes kept), "
               "whose full system runs each load step from the previous "
               "one; convert it yourself (python -m solver convert) for "
               "other gaps, or use the condensed system")

#: What friction on the full system of a ``.npz`` under the petsc engine
#: does not do: it converts the ``.npz`` to a folder on the fly and runs
#: the folder's Krylov friction (:mod:`solver.mpi.krylov_friction`), so
#: it refuses what the folder refuses, but maps ``gap`` to the
#: conversion's and keeps the roller nodes (``rollers=True``).
CONVERTED_RULES = (
    _on_the_fly("formulation", "the Krylov friction runs the projection "
                "formulation (formulation='projection'); the thesis's "
                "split runs on the serial engine",
                lambda c, s, g: s["formulation"] == "thesis",
                "formulation='thesis'"),
    _on_the_fly("method", "the Krylov friction is the active set method "
                "(φ_min)", lambda c, s, g: s["method"] != "min",
                "method='fb'"),
    _on_the_fly("ksp", "friction on the full system runs by Krylov on "
                "the ranks' rows (ksp='gamg' or 'hypre'); MUMPS would "
                "factorise the whole K for every Newton system: give "
                "ksp='gamg' or 'hypre', or use the condensed system",
                lambda c, s, g: s["ksp"] not in ("gamg", "hypre"),
                "system='full' without ksp='gamg' or 'hypre'"),
    _on_the_fly("rollers", _ON_THE_FLY,
                lambda c, s, g: "rollers" in g and not s["rollers"],
                "rollers=False"),
) + tuple(
    _on_the_fly(name, _ON_THE_FLY, lambda c, s, g, name=name: name in g)
    for name in ("search_interval", "gap_scale", "options", "geometry",
                 "on_step"))


#: The refused combinations, checked in order (the first that applies is
#: reported).
RULES = tuple(
    list(PARTITIONED_RULES)
    + [_friction_only(n) for n in FRICTION_ONLY]
    + [_frictionless_only(n) for n in FRICTIONLESS_ONLY]
    + [_amg(*refusal) for refusal in AMG_REFUSALS]
    + [
        Rule("gap", "two bodies, discrete problems",
             "gap chooses how the gaps to a rigid obstacle are found; this "
             "problem's gaps are given (no mesh) or the mortar's weighted "
             "gaps (two bodies)",
             lambda c, s, g: "gap" in g and c.bodies != "rigid"),
        Rule("search_interval", "3D, two bodies, discrete problems",
             "it searches the parameter t of a 2D obstacle curve",
             lambda c, s, g: "search_interval" in g
             and (c.bodies != "rigid" or c.dim != 2)),
        Rule("variant", "one body", "it chooses the coupling of two bodies",
             lambda c, s, g: "variant" in g and c.bodies != "two-body"),
        Rule("engine", "discrete problems",
             "the petsc engine partitions a mesh by nodes (one body against "
             "a rigid obstacle, or two bodies by the dual mortar); a "
             "problem without a mesh runs on the serial engine",
             lambda c, s, g: c.engine == "petsc"
             and c.bodies == "discrete", "engine='petsc'"),
        Rule("formulation", "3D",
             "the thesis's split formulation (Δu_t⁺, Δu_t⁻) is 2D-only; "
             "use formulation='projection'",
             lambda c, s, g: s["formulation"] == "thesis" and c.dim == 3,
             "formulation='thesis'"),
        Rule("start", "the full system",
             "the nested start needs the condensed system",
             lambda c, s, g: s["start"] == "nested" and not s["condense"],
             "start='nested'"),
        Rule("start", "the full system",
             "the full system starts from the thesis's u = 0 (a body held "
             "by contact only: from its rigid placement on the obstacle); "
             "the free start (no contact force, u = K⁻¹f) is the condensed "
             "system's",
             lambda c, s, g: s["start"] == "free" and not s["condense"],
             "start='free'"),
        Rule("start", "3D",
             "the nested start coarsens along the ordered 2D curve Γc; 3D "
             "starts free",
             lambda c, s, g: s["start"] == "nested" and c.dim == 3,
             "start='nested'"),
        Rule("start", "candidates=True",
             "the nested start condenses onto every DOF of Γc, not onto "
             "candidates",
             lambda c, s, g: s["start"] == "nested" and s["candidates"],
             "start='nested'"),
        Rule("x0", "start given", "give either x0 or start",
             lambda c, s, g: "x0" in g and "start" in g),
        Rule("candidates", "the full system",
             "the candidates are a condensation (system='condensed')",
             lambda c, s, g: s["candidates"] and not s["condense"],
             "candidates=True"),
        Rule("candidates", "friction with formulation='thesis'",
             "friction on candidates needs formulation='projection'",
             lambda c, s, g: s["candidates"] and c.contact == "friction"
             and s["formulation"] == "thesis", "candidates=True"),
        Rule("margin", "without candidates",
             "it is the candidates' screening margin (candidates=True)",
             lambda c, s, g: "margin" in g and not s["candidates"]),
        Rule("backend", "the full system",
             "the full system's Newton steps are solved by SciPy's sparse "
             "LU (backend='superlu' or backend='auto'); the other backends "
             "factorise K for the condensed system",
             lambda c, s, g: not s["condense"] and c.engine == "serial"
             and s["backend"] not in ("auto", "superlu", "amg"),
             "backend='pardiso' or 'cholmod'"),
        Rule("backend", "the petsc engine",
             "the petsc engine factorises with MUMPS; backend chooses the "
             "serial engine's solver",
             lambda c, s, g: c.engine == "petsc"
             and s["backend"] != "auto", "backend"),
        Rule("ksp", "the serial engine, the condensed system",
             "it solves the petsc engine's full-system Newton steps "
             "(engine='petsc', system='full')",
             lambda c, s, g: "ksp" in g and (c.engine != "petsc"
                                             or s["condense"])),
        Rule("formulation", "a body held by contact only",
             "the split is singular where p = 0, and a floating body's "
             "frictionless first step leaves its slide free too (φ_FB "
             "stalls there); use formulation='projection' (condensed or "
             "system='full')",
             lambda c, s, g: c.support == "floating"
             and c.contact == "friction" and s["formulation"] == "thesis",
             "formulation='thesis'"),
        Rule("system", "a body held by contact only, petsc engine",
             "the petsc engine's full system solves its Newton systems "
             "with K itself (MUMPS or CG + GAMG), singular here; its "
             "condensed system (the default) solves the body with K⁺ and "
             "the modes' amplitudes",
             lambda c, s, g: c.support == "floating" and c.engine == "petsc"
             and not s["condense"], "system='full'"),
        Rule("candidates", "a body held by contact only",
             "its modes' amplitudes are condensed with every DOF of Γc",
             lambda c, s, g: c.support == "floating" and s["candidates"],
             "candidates=True"),
    ] + list(CONVERTED_RULES))


def _choice(name, value, allowed):
    if value not in allowed:
        raise SolverError(f"{name} must be one of {allowed}, got {value!r}")


def resolve(case, options):
    """The settings of a call: every option checked against its values and
    :data:`RULES` (SolverError, one line), the defaults of the case filled
    in, plus ``condense`` and ``candidates`` (bool), ``start`` ("nested",
    "free", "x0", "zero"; "rigid" on the full system of a body held by
    contact only; None with friction), ``rollers``, ``gap``."""
    given = given_options(options)
    s = dict(options)
    friction = case.contact == "friction"

    _choice("system", s["system"], SYSTEMS)
    if s["start"] is not None:
        _choice("start", s["start"], STARTS)
    s["formulation"] = s["formulation"] or "projection"
    _choice("formulation", s["formulation"], FORMULATIONS)
    s["method"] = s["method"] or (default_method(s["formulation"])
                                  if friction else "min")
    _choice("method", s["method"], METHODS)
    s["coulomb"] = s["coulomb"] or "lagged"
    _choice("coulomb", s["coulomb"], COULOMB)
    if s["gap"] is not None:
        _choice("gap", s["gap"], GAP_MODES)
    if case.bodies == "rigid":
        s["gap"] = s["gap"] or "obstacle"
    _choice("backend", s["backend"], ("auto",) + BACKENDS + ITERATIVE)
    if s["ksp"] is not None:
        _choice("ksp", s["ksp"], KSPS)
    if s["variant"] is not None:
        _choice("variant", s["variant"], VARIANTS)
    if s["rollers"] is not None and not isinstance(s["rollers"], bool):
        raise SolverError(f"rollers must be True or False, got "
                          f"{s['rollers']!r}")
    _check_numbers(s)
    thesis = friction and s["formulation"] == "thesis"
    s["condense"] = {"auto": not thesis, "condensed": True,
                     "full": False}[s["system"]]
    floating = case.support == "floating"
    if s["backend"] == "amg" and s["system"] == "auto":
        s["condense"] = False  # the active set method's full system
    if s["candidates"] is None:
        s["candidates"] = s["condense"] and not floating and (
            (case.dim == 3 and not thesis) if friction
            else (case.dim == 3 or case.engine == "petsc"))
    s["candidates"] = bool(s["candidates"])
    if not friction:
        if s["x0"] is not None and s["start"] is None:
            s["start"] = "x0"
        elif not s["condense"] and s["start"] is None:
            s["start"] = "rigid" if floating else "zero"
        elif s["start"] is None:
            s["start"] = "nested" if case.dim == 2 \
                and not s["candidates"] else "free"
    if s["rollers"] is None:
        s["rollers"] = True
    geometry = s["geometry"]
    if geometry is not None:  # it decided gap and rollers: no contradiction
        if "gap" in given and s["gap"] != geometry.mode:
            raise SolverError(f"gap={s['gap']!r} contradicts the geometry "
                              f"given (gaps from {geometry.mode!r})")
        if "rollers" in given and not s["rollers"] \
                and geometry.has_rollers:
            raise SolverError("rollers=False contradicts the geometry "
                              "given (it has roller nodes)")
    for rule in RULES:
        if rule.applies(case, s, given):
            raise SolverError(rule.message(case, s))
    if case.engine == "petsc" and not s["condense"]:
        s["ksp"] = s["ksp"] or "mumps"
    return s


def auto_eligible(case, given):
    """Whether ``backend="auto"`` may choose the iterative path for this
    call: a meshed body against a rigid obstacle or two bodies by the dual
    mortar, supported or held by contact only, on the serial engine,
    frictionless or with friction by the projection formulation (either
    bound), with none of the options that path refuses
    (:data:`AMG_REFUSALS`) or that need the condensed system."""
    projection = given["formulation"] in (None, "projection")
    return ((case.contact == "frictionless" or projection)
            and case.bodies in ("rigid", "two-body")
            and case.engine == "serial" and given["backend"] == "auto"
            and given["method"] in (None, "min")
            and given["system"] == "auto"
            and all(given[name] is None for name in (
                "start", "candidates", "margin", "options")))


def _check_numbers(s):
    """SolverError for a tolerance, iteration count or scale that is not a
    number in its range."""
    import math

    tol, max_iter = s["tol"], s["max_iter"]
    if not isinstance(tol, (int, float)) or isinstance(tol, bool) \
            or not 0 < tol < 1 or not math.isfinite(tol):
        raise SolverError(f"tol must be a number in (0, 1), got {tol!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) \
            and not (hasattr(max_iter, "__index__")) or max_iter < 0:
        raise SolverError(f"max_iter must be an integer >= 0, got "
                          f"{max_iter!r}")
    scale = s["gap_scale"]
    if scale is not None and not (isinstance(scale, (int, float))
                                  and math.isfinite(scale) and scale > 0):
        raise SolverError(f"gap_scale must be positive and finite, got "
                          f"{scale!r}")


def check_geometry_rules(case, settings, geometry):
    """The refusals that need the contact geometry (SolverError): roller
    nodes with the thesis's split formulation, and with the petsc
    engine's full system (its node frames must be orthogonal)."""
    oblique = np.flatnonzero(geometry.oblique)
    if case.contact == "friction" and len(oblique):
        raise SolverError(
            f"friction is not supported for {case} at {len(oblique)} "
            f"contact node(s) (positions {_first(oblique)} along Γc) whose "
            "prescribed DOFs have a share of the contact normal: the "
            "Coulomb cone does not survive the projection onto their free "
            "DOFs; free those DOFs, or make the nodes supports "
            "(rollers=False)")
    rollers = int(geometry.rollers.sum())
    if not rollers:
        return
    if case.contact == "friction" and settings["formulation"] == "thesis":
        raise SolverError(
            f"formulation='thesis' is not supported for {case}: the split "
            f"formulation does not take roller nodes ({rollers} contact "
            "nodes with a Dirichlet component on a symmetry plane); use "
            "formulation='projection', or rollers=False to make them "
            "supports")
    if case.engine == "petsc" and not settings["condense"]:
        raise SolverError(
            f"system='full' is not supported for {case}: the petsc "
            f"engine's full system needs orthogonal node frames, and "
            f"{rollers} contact nodes are rollers; use the condensed "
            "system (friction on the full system, ksp='gamg' or 'hypre', "
            "converts the .npz on the fly and keeps them)")


def _first(values, count=5):
    text = ", ".join(str(int(v)) for v in values[:count])
    return text + (", ..." if len(values) > count else "")


def support_table():
    """The README's "What works where": one Markdown row per rule."""
    rows = ["| option | refused for | why |", "|---|---|---|"]
    groups = []  # consecutive rules of one case and reason: one row
    for rule in RULES:
        if groups and groups[-1][0] == (rule.where, rule.reason):
            groups[-1][1].append(rule.label or rule.option)
        else:
            groups.append(((rule.where, rule.reason),
                           [rule.label or rule.option]))
    for (where, reason), names in groups:
        shown = ", ".join(f"`{name}`" for name in names)
        rows.append(f"| {shown} | {where} | {reason} |")
    rows.append("| `formulation='thesis'` | roller nodes (symmetry planes) "
                "| the split formulation has no row to drop for a "
                "roller's constrained tangent (rollers=False makes them "
                "supports) |")
    rows.append("| `system='full'`, petsc engine, frictionless | roller "
                "nodes | its node frames must be orthogonal (friction on "
                "the full system converts the .npz on the fly and keeps "
                "them) |")
    rows.append("| `friction` | oblique nodes (a prescribed DOF with a share "
                "of the contact normal) | the Coulomb cone does not survive "
                "the projection onto the free DOFs |")
    return "\n".join(rows)
