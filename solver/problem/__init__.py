"""The ``.npz`` problem format: the one place that defines, writes and
checks it (see :mod:`solver.problem.format` for the layout).

Modules, each importing only those before it: :mod:`.format` (version,
keys, limits), :mod:`.checks` (generic array checks), :mod:`.meta` (the
metadata JSON), :mod:`.surface_spec` (the 3D obstacle spec),
:mod:`.geometry3d` (tetrahedra, contact triangles), :mod:`.two_body` (the
bodies and mortar segments of a two-body file, version 4),
:mod:`.geometry` (mesh keys and geometry, 2D and 3D),
:mod:`.validate` (all keys), :mod:`.core` (:class:`ContactProblem`),
:mod:`.archive` (safe reading of the members), :mod:`.load` (reading
and writing files).
"""

from .archive import Archive
from .checks import check_positive_definite
from .core import ContactProblem, validate_arrays
from .format import FORMAT_VERSION, KEYS, SYMMETRY_RTOL, format_table
from .load import load_problem, save_problem

__all__ = ["FORMAT_VERSION", "KEYS", "ContactProblem", "load_problem",
           "save_problem", "validate_arrays", "format_table",
           "check_positive_definite", "SYMMETRY_RTOL", "Archive"]
