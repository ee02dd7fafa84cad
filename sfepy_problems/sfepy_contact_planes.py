r"""
SfePy's ``elastic_contact_planes.py`` as a problem of the contact solver:
a unit cube indented by a rigid pyramid of four bounded planes (issue 35).

SfePy's example (``sfepy/examples/linear_elasticity/
elastic_contact_planes.py``) presses four planes into the top z = 0.5 of
the cube [−0.5, 0.5]³ (its mesh ``meshes/3d/cube_medium_hexa.mesh``,
10 × 10 × 10 hexahedra, in SfePy's data folder), fixed on its bottom
z = −0.5; λ = 5.769, μ = 3.846 (E = 10, ν = 0.3). Plane i passes through
the anchor A = (0, 0, 0.3) with the normal n_i = (±0.3, 0, 1) or
(0, ±0.3, 1) (pointing into the obstacle) and acts only where a point's
orthogonal projection onto it falls into the projection of a triangle
``bs`` (A and two corners of the square |x|, |y| ≤ 0.25 at z = 0.3): the
four faces of a pyramid, apex down at A, 0.2 below the top.

SfePy solves

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    + \sum_{i=1}^4 \int_{\Gamma} \ul{v} \cdot f(d_i(\ul{u})) \ul{n}_i = 0
    \;, \quad \forall \ul{v} \;,

a *penalty* at the quadrature points (order 6) of the top: the penetration
d_i = (X + u − A)·n_i of the *deformed* point, the force f(d) = k d + f₀
(k = 1e5, f₀ = 1e2, smoothed to 0 over −2f₀/k < d ≤ 0), the bounds tested
on the reference point. The contact solver solves the same body *exactly*
at the *nodes* of Γc = the top, gaps in the *reference* position, against
``{"kind": "several", "surfaces": [four "polygon"s]}``: each polygon SfePy's
plane (anchor, ``-n_i``, the vertices ``bs``), each node taking the plane of
smallest gap among those whose polygon it projects into (the same mask as
SfePy's). On this mesh 9 nodes of the top, x, y ∈ {−0.1, 0, 0.1}, project
into a polygon; those at ±0.2 fall just outside (the triangles' projections
end at |x| = 0.229 on the planes, a node's foot at 0.2385).
``notebooks/sfepy_examples.ipynb`` measures the differences.

By default SfePy solves nothing here (``_export.NO_SOLVE``); ``penalty=k``
solves SfePy's own penalty problem on the same mesh (``f0``; the example's
Newton settings, ``i_max`` iterations at most) and writes its displacement
as ``.npz`` (``u``, ``coors``, SfePy's Newton status) to ``output``;
``penalty=1e5`` is SfePy's example itself; ``quadrature='nodes'``
moves its quadrature points to the faces' vertices (``QUADRATURES``).

Usage (from the repository root)::

  sfepy-run sfepy_problems/sfepy_contact_planes.py \
      -d "output='output/sfepy_contact_planes.npz'"
  python -m solver output/sfepy_contact_planes.npz
  sfepy-run sfepy_problems/sfepy_contact_planes.py \
      -d "penalty=1e5, output='output/sfepy_contact_planes_penalty.npz'"

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
#: The example's Lamé parameters (E = 10, ν = 0.3).
LAM, MU = 5.769, 3.846
#: The example's planes: normal components, polygon size, anchor height.
DN, DS, AZ = 0.3, 0.25, 0.3
#: Per plane: SfePy's normal n (into the obstacle) and boundary points bs.
PLANES = [([DN, 0.0, 1.0], [[0.0, 0.0, AZ], [-DS, -DS, AZ], [-DS, DS, AZ]]),
          ([-DN, 0.0, 1.0], [[0.0, 0.0, AZ], [DS, -DS, AZ], [DS, DS, AZ]]),
          ([0.0, DN, 1.0], [[0.0, 0.0, AZ], [-DS, -DS, AZ], [DS, -DS, AZ]]),
          ([0.0, -DN, 1.0], [[0.0, 0.0, AZ], [-DS, DS, AZ], [DS, DS, AZ]])]
#: The penalty term's quadrature on the faces of the top: SfePy's example
#: (Gauss, order 6 per direction), or at the faces' vertices (the
#: trapezoidal rule on the reference square [0, 1]²: the penalty at the
#: nodes, lumped, as the contact solver's constraints).
QUADRATURES = {'gauss': 6,
               'nodes': (1, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
                         [0.25, 0.25, 0.25, 0.25])}
#: The example's penalty parameters and Newton settings.
K_PENALTY, F0 = 1e5, 1e2
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


def obstacle():
    """The four planes as ``several`` ``polygon``s: SfePy's anchor, its
    normal reversed (the project's points out of the obstacle), its
    boundary points."""
    return {'kind': 'several', 'surfaces': [
        {'kind': 'polygon', 'point': [0.0, 0.0, AZ],
         'normal': [-c for c in normal], 'vertices': bounds}
        for normal, bounds in PLANES]}


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
        obstacle=obstacle(),
        meta={'E': E, 'nu': nu, 'lam': LAM, 'mu': MU,
              'load': {'pyramid_apex_depth': 0.5 - AZ},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/sfepy_contact_planes.py',
              'description': "SfePy's elastic_contact_planes.py: the cube "
                             '[-0.5, 0.5]^3 indented by a rigid pyramid of '
                             'four bounded planes, apex 0.2 deep',
              'supports': 'bottom z = -0.5 fixed',
              'contact_boundary': 'top z = 0.5'})


def define(mesh=MESH, output='output/sfepy_contact_planes.npz',
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
    }
    for i, (normal, bounds) in enumerate(PLANES):
        materials[f'cp{i}'] = ({'f': [penalty or K_PENALTY, f0], '.n': normal,
                                '.a': [0.0, 0.0, AZ], '.bs': bounds},)
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
    else:  # SfePy's example: the penalty terms at order 6 on the top
        equations = {
            'elasticity': 'dw_lin_elastic.2.Omega(solid.D, v, u)' + ''.join(
                f' + dw_contact_plane.ic.Top(cp{i}.f, cp{i}.n, cp{i}.a, '
                f'cp{i}.bs, v, u)' for i in range(len(PLANES))) + ' = 0',
        }
        newton = dict(NEWTON, i_max=i_max)
    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', newton),
    }
    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
