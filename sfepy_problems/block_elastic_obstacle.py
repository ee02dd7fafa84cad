r"""
The thesis's block against an elastic body shaped like its parabola.

The rigid-limit check of issue 19: the §4 model of ``block_obstacle.py``
(the block :math:`[-5, 5] \times [-10, 10]`, E = 2e5, ν = 0.3, plane strain,
the bottom y = −10 clamped, the point force F = (4000, 0) at (−5, 10), Γc
the right edge x = 5) pressed not against the rigid parabola
:math:`\Gamma_o(t) = [5.05 + 0.005 t^2, t]` but against an **elastic body**
whose surface facing the block is that parabola: the region between x =
5.05 + 0.005 y² and x = ``x_far`` (10) for |y| ≤ 11, its far side x = 10
clamped (its "bottom"), Young's modulus ``E_ratio`` × E (ν_o = 0.3). As
E_ratio grows (1e2, 1e4, 1e6) the solution tends to the rigid-obstacle
solution of ``block_obstacle.py`` on the same block mesh.

Exported as a two-body problem (``.npz`` format version 4, issue 19;
``docs/npz-format.md``): body 0 the block (the **slave**, its right edge
bottom to top, as Γc of the rigid case), body 1 the obstacle body (the
**master**, its parabola side top to bottom; vertices exactly on the
parabola every 0.25, so the chord error is ≤ 0.005 · 0.25² / 8 ≈ 8e-5),
one mesh ``meshes/two_body_block_454.mesh`` (``meshes/two_body.py
block``: the block is ``meshes/block_454.mesh`` node for node). SfePy
builds K (block-diagonal), f (the point force) and M on Γc; it solves only
the problem without contact. Neither body floats: the block is clamped at
its bottom, the obstacle at its far side.

Usage::

  python meshes/two_body.py block         # the mesh, if absent
  sfepy-run sfepy_problems/block_elastic_obstacle.py \
      -d "mesh='meshes/two_body_block_454.mesh', output='output/block_elastic_1e4.npz', E_ratio=1e4"
  python -m solver output/block_elastic_1e4.npz

(``python sfepy_problems/block_elastic_obstacle.py -d "..."`` is the same,
quiet: ``_export.py``.) Compare with ``python sfepy_problems/block_obstacle.py
-d "mesh='meshes/block_454.mesh', output='output/block_454.npz'"``: the
block's nodes are the first 257 nodes of the two-body mesh, in the same
order.

Parameters (``-d``): ``mesh``, ``output``, ``E`` (2e5), ``nu`` (0.3),
``E_ratio`` (1e4), ``nu_obstacle`` (0.3), ``plane`` ('strain'), ``F``
((4000, 0)), ``x_far`` (10, must be the mesh's), ``verbose``,
``solve`` (True: SfePy also solves the unconstrained problem and writes
its ``.vtk``, a check; False: export only, ``_export.NO_SOLVE``, see
``block_obstacle.py``).
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates (gmsh noise is ~1e-12).
TOL = 1e-8


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


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M and the interface segments."""
    conf = pb.conf.options
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load='dw_point_load.0.Load(load.val, v)', obstacle=None,
        mortar=dict(slave='Gamma_c', master='Gamma_o',
                    bodies=['Block', 'Obstacle']),
        meta=conf.meta | {'mesh': op.basename(pb.conf.filename_mesh)})


def define(mesh='meshes/two_body_block_454.mesh',
           output='output/block_elastic.npz', E=2e5, nu=0.3, E_ratio=1e4,
           nu_obstacle=0.3, plane='strain', F=(4000.0, 0.0), x_far=10.0,
           solve=True, verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    load_point = (-5.0, 10.0)
    E_obstacle = float(E_ratio) * E

    meta = {
        'E': E, 'nu': nu, 'plane': plane,
        'bodies': [{'name': 'block', 'E': E, 'nu': nu},
                   {'name': 'parabola body', 'E': E_obstacle,
                    'nu': nu_obstacle}],
        'slave_body': 0, 'master_body': 1, 'E_ratio': float(E_ratio),
        'load': {'point_force': list(map(float, F)),
                 'at': list(load_point)},
        'obstacle_body': 'x from 5.05 + 0.005 y**2 to x_far, |y| <= 11',
        'x_far': float(x_far),
        'problem_file': 'sfepy_problems/block_elastic_obstacle.py',
        'description': 'thesis block (slave) against an elastic body shaped '
                       'like the thesis parabola (master)',
        'supports': 'block bottom y = -10 clamped; obstacle side x = x_far '
                    'clamped',
        'contact_boundary': 'slave: block right edge x = 5; master: the '
                            'parabola x = 5.05 + 0.005 y**2',
    }
    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': bool(solve),  # no solve: no .vtk of a zero field
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'meta': meta,
    }

    regions = {
        'Omega': 'all',
        'Block': 'cells of group 1',
        'Obstacle': 'cells of group 2',
        'Bottom': (f'vertices in (y < {-10 + TOL})', 'facet'),
        'Right': (f'vertices in (x > {5 - TOL}) & (x < {5 + TOL})', 'facet'),
        'Surface': ('vertices of surface', 'facet'),
        'Gamma_D': ('r.Bottom *v r.Block', 'facet'),
        'Gamma_c': ('r.Right *v r.Block', 'facet'),
        'Near': (f'vertices in (x < {5.05 + 0.005 * 11 ** 2 + TOL})',
                 'facet'),
        'NearO': ('r.Near *v r.Obstacle', 'facet'),
        'Gamma_o': ('r.Surface *e r.NearO', 'facet'),
        'Far': (f'vertices in (x > {x_far - TOL})', 'facet'),
        'Load': (f'vertices in (x < {-5 + TOL}) & (y > {10 - TOL})',
                 'vertex'),
    }

    materials = {
        'solid': ({'D': {
            'Block': stiffness_from_youngpoisson(2, E, nu, plane=plane),
            'Obstacle': stiffness_from_youngpoisson(2, E_obstacle,
                                                    nu_obstacle,
                                                    plane=plane)}},),
        'load': ({'.val': nm.asarray(F, dtype=nm.float64)},),
    }

    fields = {
        'displacement': ('real', 'vector', 'Omega', 1),
        'scalar': ('real', 'scalar', 'Omega', 1),
    }

    variables = {
        'u': ('unknown field', 'displacement', 0),
        'v': ('test field', 'displacement', 'u'),
        'p': ('unknown field', 'scalar', 1),
        'q': ('test field', 'scalar', 'p'),
    }

    ebcs = {
        'clamped': ('Gamma_D', {'u.all': 0.0}),
        'far': ('Far', {'u.all': 0.0}),
    }

    integrals = {'i': 2}

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u)
         = dw_point_load.0.Load(load.val, v)""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6,
                                  'eps_r': 1e-12} if solve
                   else dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
