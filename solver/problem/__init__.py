"""The ``.npz`` problem format: the one place that defines, writes and
checks it. Modules, each importing only those before it: :mod:`.format`
(version, keys, limits), :mod:`.checks`, :mod:`.meta`,
:mod:`.surface_spec`, :mod:`.geometry3d`, :mod:`.two_body`,
:mod:`.geometry`, :mod:`.validate` (all keys), :mod:`.core`
(:class:`ContactProblem`), :mod:`.archive` (safe reading) and
:mod:`.load` (reading and writing files)."""

from .archive import Archive
from .checks import check_positive_definite
from .core import ContactProblem, validate_arrays
from .format import FORMAT_VERSION, KEYS, SYMMETRY_RTOL, format_table
from .load import load_problem, save_problem

__all__ = ["FORMAT_VERSION", "KEYS", "ContactProblem", "load_problem",
           "save_problem", "validate_arrays", "format_table",
           "check_positive_definite", "SYMMETRY_RTOL", "Archive"]
