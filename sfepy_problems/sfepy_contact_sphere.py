r"""
SfePy's ``elastic_contact_sphere.py`` as a problem of the contact solver:
a unit cube indented by a rigid sphere (issue 35).

SfePy's example (``sfepy/examples/linear_elasticity/
elastic_contact_sphere.py``) presses the sphere of centre C = (0, 0, 1) and
radius R = 0.8 into the top z = 0.5 of the cube [−0.5, 0.5]³ (its mesh
``meshes/3d/cube_medium_hexa.mesh``, 10 × 10 × 10 hexahedra, in SfePy's data
folder); the cube is fixed on its bottom z = −0.5, the material is
isotropic with the Lamé parameters λ = 5.769, μ = 3.846 (E = 10, ν = 0.3).
The sphere's lowest point z = 0.2 lies 0.3 below the top: the indentation
is the initial overlap of the sphere and the cube.

SfePy solves

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    + \int_{\Gamma} \ul{v} \cdot f(d(\ul{u})) \ul{n}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

a *penalty*: at the quadrature points of the top face (order 6) in their
*deformed* position X + u, the penetration d = R − |X + u − C| gives the
force f(d) = k d + f₀ along the deformed normal n(u) (k = 1e5, f₀ = 1e-2,
smoothed to 0 over −2f₀/k < d ≤ 0). The contact solver solves the same
body *exactly*: u_n ≤ s, λ ≥ 0, λ (s − u_n) = 0 at the *nodes* of Γc = the
top face, the gap s and the normal fixed in the *reference* position
(the obstacle ``{"kind": "sphere", "center": [0, 0, 1], "radius": 0.8}``,
gaps along its normals). ``notebooks/sfepy_examples.ipynb`` measures the
three differences.

By default SfePy solves nothing here (the export runs on the initial state,
``_export.NO_SOLVE``); ``penalty=k`` instead solves SfePy's own penalty
problem of the example on the same mesh (with ``f0``, SfePy's Newton
settings of the example, ``i_max`` its iterations at most) and writes its
displacement as ``.npz`` (keys ``u``, the nodal displacement (n, 3), and
``coors``) to ``output``; ``penalty=1e5`` is SfePy's example itself; ``quadrature='nodes'``
moves its quadrature points to the faces' vertices (``QUADRATURES``).

Usage (from the repository root)::

  sfepy-run sfepy_problems/sfepy_contact_sphere.py \
      -d "output='output/sfepy_contact_sphere.npz'"
  python -m solver output/sfepy_contact_sphere.npz
  sfepy-run sfepy_problems/sfepy_contact_sphere.py \
      -d "penalty=1e5, output='output/sfepy_contact_sphere_penalty.npz'"

The first prints ``exported 3630 DOFs, 121 contact nodes -> PATH``.
Parameters (``-d``): ``mesh`` (default SfePy's ``cube_medium_hexa.mesh``),
``output``, ``penalty``, ``f0``, ``i_max``, ``quadrature``, ``verbose``.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy import data_dir
from sfepy.mechanics.matcoefs import stiffness_from_lame

#: The example's mesh, in SfePy's data folder.
MESH = op.join(data_dir, 'meshes', '3d', 'cube_medium_hexa.mesh')
#: The example's Lamé parameters (E = 10, ν = 0.3) and sphere.
LAM, MU = 5.769, 3.846
CENTRE, RADIUS = [0.0, 0.0, 1.0], 0.8
#: The penalty term's quadrature on the faces of the top: SfePy's example
#: (Gauss, order 6 per direction), or at the faces' vertices (the
#: trapezoidal rule on the reference square [0, 1]²: the penalty at the
#: nodes, lumped, as the contact solver's constraints).
QUADRATURES = {'gauss': 6,
               'nodes': (1, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
                         [0.25, 0.25, 0.25, 0.25])}
#: The example's penalty parameters and Newton settings.
K_PENALTY, F0 = 1e5, 1e-2
NEWTON = {'i_max': 50, 'eps_a': 1e-14, 'eps_r': 1e-8, 'eps_mode': 'or',
          'step_red': 0.8, 'ls_on': 2.0, 'check': 0, 'delta': 1e-6}


def _load_export():
    """``sfepy_problems/_export.py`` by path (this folder is not a package)."""
    name = '_contact_ssn_sfepy_export'
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, op.join(op.dirname(op.abspath(__file__)), '_export.py'))
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def young_poisson(lam, mu):
    """(E, ν) of the Lamé parameters λ, μ."""
    return mu * (3 * lam + 2 * mu) / (lam + mu), lam / (2 * (lam + mu))


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: assemble K, f = 0, M, write the ``.npz``
    (or, with ``penalty``, SfePy's penalty displacement)."""
    conf = pb.conf.options
    if conf.penalty is not None:
        return _load_export().save_displacement(pb, variables, conf.export)
    E, nu = young_poisson(LAM, MU)
    return _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle={'kind': 'sphere', 'center': CENTRE, 'radius': RADIUS},
        meta={'E': E, 'nu': nu, 'lam': LAM, 'mu': MU,
              'load': {'sphere_overlap': 0.3},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/sfepy_contact_sphere.py',
              'description': "SfePy's elastic_contact_sphere.py: the cube "
                             '[-0.5, 0.5]^3 indented 0.3 by the rigid '
                             'sphere |x - (0, 0, 1)| <= 0.8',
              'supports': 'bottom z = -0.5 fixed',
              'contact_boundary': 'top z = 0.5'})


def define(mesh=MESH, output='output/sfepy_contact_sphere.npz',
           penalty=None, f0=F0, i_max=NEWTON['i_max'], quadrature='gauss',
           verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'

    filename_mesh = op.abspath(mesh)
    options = {
        'output_dir': op.dirname(op.abspath(output)),
        'output_format': 'vtk',
        'save_results': False,
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        'export': op.abspath(output),
        'penalty': penalty,
    }
    regions = {
        'Omega': 'all',
        'Bottom': ('vertices in (z < -0.499)', 'facet'),
        'Top': ('vertices in (z > 0.499)', 'facet'),
        'Gamma_c': ('copy r.Top', 'facet'),
    }
    materials = {
        'solid': ({'D': stiffness_from_lame(dim=3, lam=LAM, mu=MU)},),
        'cs': ({'f': [penalty or K_PENALTY, f0], '.c': CENTRE,
                '.r': RADIUS},),
    }
    fields = {
        'displacement': ('real', 'vector', 'Omega', 1),
        'scalar': ('real', 'scalar', 'Omega', 1),
    }
    variables = {
        'u': ('unknown field', 'displacement', 0),
        'v': ('test field', 'displacement', 'u'),
        # Only for assembling M in the export hook:
        'p': ('unknown field', 'scalar', 1),
        'q': ('test field', 'scalar', 'p'),
    }
    ebcs = {
        'fixed': ('Bottom', {'u.all': 0.0}),
    }
    if quadrature not in QUADRATURES:
        raise ValueError(f'quadrature must be one of {sorted(QUADRATURES)}, '
                         f'got {quadrature!r}')
    integrals = {'i': 2, 'ic': QUADRATURES[quadrature]}
    if penalty is None:
        equations = {
            'balance_of_forces': 'dw_lin_elastic.i.Omega(solid.D, v, u) = 0',
        }
        newton = dict(export.NO_SOLVE)
    else:  # SfePy's example: the penalty term at order 6 on the top
        equations = {
            'elasticity': """dw_lin_elastic.2.Omega(solid.D, v, u)
             + dw_contact_sphere.ic.Top(cs.f, cs.c, cs.r, v, u) = 0""",
        }
        newton = dict(NEWTON, i_max=i_max)
    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', newton),
    }
    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
