"""Contact systems built on the finite element data of a problem file,
dimension-free: the geometry layer hands over per-node frames and gaps
(:mod:`.geometry`); the drivers run the project's semismooth Newton on
the frictionless system (:mod:`.frictionless`) or the load steps of
Coulomb friction (:mod:`.friction`), on a reduction chosen by a strategy
(:mod:`.strategies`) with the linear algebra of an engine (:mod:`.engine`),
and verify every answer (:mod:`.verify`); two bodies become a nodewise
problem (:mod:`.two_body`). The public front is :func:`solver.solve`."""

from .engine import IterativeEngine, SerialEngine
from .friction.driver import (COULOMB, FORMULATIONS, default_method,
                              run_friction)
from .friction.system import FrictionSystem
from .frictionless.driver import run_frictionless
from .frictionless.system import FrictionlessSystem
from .geometry import GAP_MODES, ContactGeometry, contact_geometry
from .result import ContactResult
from .strategies.floating import check_load as check_floating_load
from .strategies.floating import \
    check_friction_load as check_floating_friction
from .two_body import TwoBodyMap

__all__ = ["SerialEngine", "IterativeEngine", "GAP_MODES", "ContactGeometry",
           "contact_geometry", "FrictionlessSystem", "FrictionSystem",
           "run_frictionless", "run_friction", "default_method", "FORMULATIONS",
           "COULOMB",
           "ContactResult", "TwoBodyMap", "check_floating_load",
           "check_floating_friction"]
