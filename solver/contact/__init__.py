"""Contact systems built on the finite element data of a problem file."""

from .friction.driver import COULOMB, FORMULATIONS, FrictionSystem, solve_friction
from .frictionless.driver import (GAP_MODES, ContactGeometry, FrictionlessSystem,
                           contact_geometry, solve_frictionless)
from .two_body import solve_two_body

__all__ = ["GAP_MODES", "ContactGeometry", "FrictionlessSystem",
           "contact_geometry", "solve_frictionless", "FORMULATIONS",
           "COULOMB", "FrictionSystem", "solve_friction", "solve_two_body"]
