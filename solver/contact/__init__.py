"""Contact systems built on the finite element data of a problem file."""

from .frictionless import (GAP_MODES, ContactGeometry, FrictionlessSystem,
                           contact_geometry, solve_frictionless)

__all__ = ["GAP_MODES", "ContactGeometry", "FrictionlessSystem",
           "contact_geometry", "solve_frictionless"]
