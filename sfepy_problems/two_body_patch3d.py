r"""
The 3D contact patch test: two stacked elastic boxes, non-matching
unstructured interface meshes (dual mortar on triangles).

Exports a 3D two-body problem (``.npz`` format version 4 on tetrahedra,
``docs/npz-format.md``): the upper box :math:`[0, 1]^2 \times [0.5, 1]`
(body 0) and the lower box :math:`[0, 1]^2 \times [0, 0.5]` (body 1), meshed
independently by gmsh (``meshes/two_body_patch3d.mesh``, sizes 0.3 and
0.22: irregular interface triangles that do not match). SfePy assembles K
(block-diagonal), f and the slave boundary matrix M, and solves nothing
(3D: ``_export.NO_SOLVE``); the contact solver computes the mortar
matrices and solves.

Find :math:`\ul{u}` such that

.. math::
    \sum_{b=0,1} \int_{\Omega_b} D^b_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    = 0 \;, \quad \forall \ul{v} \;,

:math:`D^b` isotropic (E0, ν0; E1, ν1), with u_z = 0 on the lower box's
bottom z = 0 and u_z = −δ on the upper box's top z = 1, and, on the edges
of those two faces, u_x = 0 where x = 0 and u_y = 0 where y = 0 (off the
interface: every slave node is a free contact node). Both boxes may expand
sideways: the exact solution is uniaxial stress σ_zz = −p in both, linear
in each box, which a P1 mortar discretisation reproduces exactly, with

.. math::
    p = \delta / (h_0 / E_0 + h_1 / E_1) \;,

h0 = h1 = 0.5 (``meta["p_exact"]``): the interface pressure is uniform and
equal to it at every slave node. ``slave='upper'`` (default; the coarser
side) or ``'lower'``: the other order.

**Sliding** (``load='slide'``): the lower bottom and the upper top clamped,
the top moved in two load stages (``load_path_*``): (1) to (0, 0, −δ),
frictionless, ``steps_normal`` steps; (2) to (``shift`` · (cos θ, sin θ),
−δ), θ = ``angle`` degrees, with friction f_c (given to the solver),
``steps_shear`` steps. The default shift 0.05 = 50 δ is far beyond the
elastic shear, so the interface slips fully and the total friction force
is f_c times the normal force.

Usage::

  python meshes/two_body_patch3d.py -o meshes/two_body_patch3d.mesh
  sfepy-run sfepy_problems/two_body_patch3d.py \
      -d "mesh='meshes/two_body_patch3d.mesh', output='output/patch3d.npz'"
  python -m solver output/patch3d.npz
  sfepy-run sfepy_problems/two_body_patch3d.py \
      -d "mesh='meshes/two_body_patch3d.mesh', output='output/patch3d_slide.npz', load='slide'"
  python -m solver output/patch3d_slide.npz --friction 0.3

Parameters (``-d``): ``mesh``, ``output``, ``E0`` (1e5), ``nu0`` (0.2),
``E1`` (2e5), ``nu1`` (0.3), ``delta`` (1e-3), ``slave`` ('upper' or
'lower'), ``load`` ('press' or 'slide'), ``shift`` (0.05), ``angle`` (0),
``steps_normal`` (1), ``steps_shear`` (4), ``verbose``.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates.
TOL = 1e-8

#: The boxes' height.
HEIGHT = 0.5


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
    """``post_process_hook_final``: K, f, M and the interface triangles."""
    conf = pb.conf.options
    slave_body = 0 if conf.slave == 'upper' else 1
    p_exact = conf.delta / sum(HEIGHT / E for E, _ in conf.bodies)
    E, nu = conf.bodies[slave_body]
    stages, load = None, {'prescribed_displacement_z': -conf.delta,
                          'on': 'upper top z = 1'}
    supports = ('lower bottom u_z = 0, upper top u_z = -delta; u_x = 0 on '
                'their edges x = 0, u_y = 0 on their edges y = 0')
    if conf.load == 'slide':
        stages = [dict(dirichlet=(0.0, 0.0, 1.0), load=0.0,
                       steps=conf.steps_normal, friction=0.0),
                  dict(dirichlet=(1.0, 1.0, 1.0), load=0.0,
                       steps=conf.steps_shear, friction=1.0)]
        load = {'stages': ['press: upper top to (0, 0, -delta), '
                           'frictionless',
                           'slide: upper top to (shift cos, shift sin, '
                           '-delta), friction'],
                'shift': conf.shift, 'angle': conf.angle,
                'on': 'upper top z = 1 (clamped)'}
        supports = 'lower bottom clamped; upper top moved, clamped'
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=None, load_path=stages,
        mortar=dict(slave=conf.regions_slave_master[0],
                    master=conf.regions_slave_master[1],
                    bodies=['Upper', 'Lower']),
        meta={'E': E, 'nu': nu,
              'bodies': [{'name': 'upper box', 'E': conf.bodies[0][0],
                          'nu': conf.bodies[0][1]},
                         {'name': 'lower box', 'E': conf.bodies[1][0],
                          'nu': conf.bodies[1][1]}],
              'slave_body': slave_body, 'master_body': 1 - slave_body,
              'delta': conf.delta,
              **({'p_exact': p_exact} if conf.load == 'press' else {}),
              'area': 1.0, 'heights': [HEIGHT, HEIGHT], 'load': load,
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/two_body_patch3d.py',
              'description': '3D contact patch test: two stacked boxes, '
                             'non-matching unstructured interface meshes',
              'supports': supports,
              'contact_boundary': f'slave: the {conf.slave} box\'s side '
                                  'of z = 0.5'})


def define(mesh='meshes/two_body_patch3d.mesh',
           output='output/patch3d.npz', E0=1e5, nu0=0.2, E1=2e5, nu1=0.3,
           delta=1e-3, slave='upper', load='press', shift=0.05, angle=0.0,
           steps_normal=1, steps_shear=4, verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    if slave not in ('upper', 'lower'):
        raise ValueError(f"slave must be 'upper' or 'lower', got {slave!r}")
    if load not in ('press', 'slide'):
        raise ValueError(f"load must be 'press' or 'slide', got {load!r}")
    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    upper_side, lower_side = 'Gamma_upper', 'Gamma_lower'
    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': False,  # SfePy solves nothing (NO_SOLVE)
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'bodies': [(E0, nu0), (E1, nu1)], 'delta': delta, 'slave': slave,
        'load': load, 'shift': float(shift), 'angle': float(angle),
        'steps_normal': int(steps_normal), 'steps_shear': int(steps_shear),
        'regions_slave_master': ((upper_side, lower_side) if slave == 'upper'
                                 else (lower_side, upper_side)),
    }

    ends = f'((z < {TOL}) | (z > {2 * HEIGHT - TOL}))'
    regions = {
        'Omega': 'all',
        'Upper': 'cells of group 1',
        'Lower': 'cells of group 2',
        'Interface': (f'vertices in (z > {HEIGHT - TOL}) & '
                      f'(z < {HEIGHT + TOL})', 'facet'),
        # the interface facets of each box (the bodies share no node)
        upper_side: ('r.Interface *v r.Upper', 'facet'),
        lower_side: ('r.Interface *v r.Lower', 'facet'),
        'Bottom': (f'vertices in (z < {TOL})', 'facet'),
        'Top': (f'vertices in (z > {2 * HEIGHT - TOL})', 'facet'),
        'EdgeX': (f'vertices in (x < {TOL}) & {ends}', 'vertex'),
        'EdgeY': (f'vertices in (y < {TOL}) & {ends}', 'vertex'),
    }

    materials = {
        'solid': ({'D': {
            'Upper': stiffness_from_youngpoisson(3, E0, nu0),
            'Lower': stiffness_from_youngpoisson(3, E1, nu1)}},),
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

    if load == 'press':
        ebcs = {
            'bottom': ('Bottom', {'u.2': 0.0}),
            'pressed': ('Top', {'u.2': -delta}),
            'edge_x': ('EdgeX', {'u.0': 0.0}),
            'edge_y': ('EdgeY', {'u.1': 0.0}),
        }
    else:  # the upper box dragged over the clamped lower one
        theta = nm.radians(angle)
        ebcs = {
            'bottom': ('Bottom', {'u.all': 0.0}),
            'moved': ('Top', {'u.0': shift * nm.cos(theta),
                              'u.1': shift * nm.sin(theta),
                              'u.2': -delta}),
        }

    integrals = {'i': 2}

    equations = {
        'balance_of_forces': """dw_lin_elastic.i.Omega(solid.D, v, u) = 0""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
