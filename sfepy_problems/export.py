"""The export helper of SfePy problem files, under its public name.

A problem file outside this repository writes the contact solver's
``.npz`` from its ``post_process_hook_final`` with ::

    from sfepy_problems import export

    def export_hook(pb, variables):
        export.export_contact_problem(
            pb, variables, 'ring.npz',
            stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
            obstacle={'x': '2.001*cos(t)', 'y': '2.001*sin(t)'},
            meta={'E': 2e5, 'nu': 0.3, 'plane': 'strain', 'load': ...,
                  'mesh': 'ring.mesh'})

(``docs/own-problem.md`` walks through such a file). The functions live in
``sfepy_problems/_export.py``, which the problem files of this folder load
by path; this module re-exports its public names (``__all__``) for code
that imports the installed package. SfePy is imported only when they run.
"""

from ._export import *  # noqa: F401,F403 (the public names, __all__)
from ._export import __all__  # noqa: F401
