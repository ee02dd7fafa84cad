r"""
Contact patch test: two stacked elastic blocks, non-matching interface.

Exports a two-body problem (``.npz`` format version 4, issue 19;
``docs/npz-format.md``) for the dual mortar contact solver: the lower block
:math:`\Omega_0 = [0, 1] \times [0, 0.5]` (body 0) and the upper block
:math:`\Omega_1 = [0, 1] \times [0.5, 1]` (body 1), meshed independently
(``meshes/two_body_patch.mesh``: 5 interface segments below, 8 above, so
no interior node of one side faces a node of the other). SfePy builds K
(block-diagonal), f and the slave boundary matrix M; the contact solver
(``python -m solver``) computes the mortar matrices and solves. SfePy
itself solves only the elasticity problem without contact (the blocks then
pass through each other).

Find :math:`\ul{u}` such that:

.. math::
    \sum_{b=0,1} \int_{\Omega_b} D^b_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    = 0 \;, \quad \forall \ul{v} \;,

:math:`D^b` the plane strain (or stress) elasticity tensor of body b (E0,
ν0; E1, ν1), with

* :math:`u_y = 0` on the lower block's bottom y = 0,
* :math:`u_x = 0` at one point of each block, its outer left corner (0, 0)
  and (0, 1),
* :math:`u_y = -\delta` on the upper block's top y = 1 (u_x free).

**No floating body.** A pressure on the top would leave the upper block
held only by the contact, with a singular K that the solver cannot
factorise, so its top is moved down by δ instead (the contract of issue
19). The supports leave both blocks free to expand sideways: the exact
solution is a uniform uniaxial stress :math:`\sigma_{yy} = -p` in both
blocks, piecewise linear, so a P1 mortar discretisation reproduces it
exactly and the interface pressure is uniform. No interface node carries
a Dirichlet condition (the x pins are off the interface), so every slave
node is a contact node. The applied pressure p is
the reaction on the top edge per its width (1), known after the solve;
for the default data it is

.. math::
    p = \delta / (h_0 / E'_0 + h_1 / E'_1) \;, \quad
    E' = E / (1 - \nu^2) \text{ (plane strain)}, \; E \text{ (plane stress)},

h0 = h1 = 0.5 the heights (u_y linear in each block, continuous at the
interface); it is exported in ``meta["p_exact"]``.

**Slave and master.** ``slave='upper'`` (default): the upper block's bottom
edge (8 segments, the finer side) is the slave, the lower block's top (5)
the master — fine slave on coarse master; ``slave='lower'``: the reverse,
coarse slave on fine master. The slave segments run with the body on
their left: left to right for the upper block's bottom, right to left for
the lower block's top.

**Sliding** (``load='slide'``): a frictional block sliding on a block
(issue 19: the total friction force is f_c times the normal force at full
slip). The lower bottom is clamped and the upper top clamped and moved in
two load stages (``load_path_*`` keys): (1) to (0, −δ), frictionless,
``steps_normal`` steps; (2) to (``shift``, −δ) with friction f_c (given to
the solver), ``steps_shear`` steps. The default shift 0.01 = 10 δ is far
beyond the elastic shear of the blocks at f_c ≤ 1 (≈ f_c p h/G ≈ 2e-3),
so the interface slips fully.

Usage::

  python meshes/two_body.py patch     # meshes/two_body_patch.mesh, if absent
  sfepy-run sfepy_problems/two_body_patch.py \
      -d "mesh='meshes/two_body_patch.mesh', output='output/patch.npz'"
  sfepy-run sfepy_problems/two_body_patch.py \
      -d "mesh='meshes/two_body_patch.mesh', output='output/patch_coarse_slave.npz', slave='lower'"
  sfepy-run sfepy_problems/two_body_patch.py \
      -d "mesh='meshes/two_body_patch.mesh', output='output/patch_slide.npz', load='slide'"
  python -m solver output/patch.npz
  python -m solver output/patch_slide.npz --friction 0.3

(``python sfepy_problems/two_body_patch.py -d "..."`` is the same, quiet:
``_export.py``.) The export prints ``exported 110 DOFs, 9 contact nodes ->
/.../output/patch.npz``.

Parameters (``-d``): ``mesh``, ``output``, ``E0`` (2e5), ``nu0`` (0.3),
``E1`` (1e5), ``nu1`` (0.2), ``plane`` ('strain'), ``delta`` (1e-3),
``slave`` ('upper' or 'lower'), ``load`` ('press' or 'slide'), ``shift``
(0.01), ``steps_normal`` (5), ``steps_shear`` (10), ``verbose``.
"""
import importlib.util
import os.path as op
import sys

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates.
TOL = 1e-8

#: The blocks: width and height of each.
WIDTH, HEIGHT = 1.0, 0.5


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


def _modulus(E, nu, plane):
    return E / (1.0 - nu ** 2) if plane == 'strain' else E


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M and the interface segments."""
    conf = pb.conf.options
    slave_body = 1 if conf.slave == 'upper' else 0
    p_exact = conf.delta / sum(HEIGHT / _modulus(E, nu, conf.plane)
                               for E, nu in conf.bodies)
    E, nu = conf.bodies[slave_body]
    stages, load = None, {'prescribed_displacement_y': -conf.delta,
                          'on': 'upper top y = 1'}
    supports = ('lower bottom u_y = 0; u_x = 0 at (0, 0) and (0, 1); upper '
                'top u_y = -delta')
    if conf.load == 'slide':
        stages = [dict(dirichlet=(0.0, 1.0), load=0.0,
                       steps=conf.steps_normal, friction=0.0),
                  dict(dirichlet=(1.0, 1.0), load=0.0,
                       steps=conf.steps_shear, friction=1.0)]
        load = {'stages': ['press: upper top to (0, -delta), frictionless',
                           'slide: upper top to (shift, -delta), friction'],
                'shift': conf.shift, 'on': 'upper top y = 1 (clamped)'}
        supports = 'lower bottom clamped; upper top u = (shift, -delta)'
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=None, load_path=stages,
        mortar=dict(slave=conf.regions_slave_master[0],
                    master=conf.regions_slave_master[1],
                    bodies=['Lower', 'Upper']),
        meta={'E': E, 'nu': nu, 'plane': conf.plane,
              'bodies': [{'name': 'lower block', 'E': conf.bodies[0][0],
                          'nu': conf.bodies[0][1]},
                         {'name': 'upper block', 'E': conf.bodies[1][0],
                          'nu': conf.bodies[1][1]}],
              'slave_body': slave_body, 'master_body': 1 - slave_body,
              'delta': conf.delta,
              **({'p_exact': p_exact} if conf.load == 'press' else {}),
              'width': WIDTH, 'heights': [HEIGHT, HEIGHT],
              'load': load,
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/two_body_patch.py',
              'description': 'contact patch test: two stacked blocks, '
                             'non-matching interface meshes',
              'supports': supports,
              'contact_boundary': f'slave: the {conf.slave} block\'s side '
                                  'of y = 0.5'})


def define(mesh='meshes/two_body_patch.mesh', output='output/patch.npz',
           E0=2e5, nu0=0.3, E1=1e5, nu1=0.2, plane='strain', delta=1e-3,
           slave='upper', load='press', shift=0.01, steps_normal=5,
           steps_shear=10, verbose=None):
    _load_export().set_verbosity(verbose)  # before SfePy's 'left over:'
    if slave not in ('upper', 'lower'):
        raise ValueError(f"slave must be 'upper' or 'lower', got {slave!r}")
    if load not in ('press', 'slide'):
        raise ValueError(f"load must be 'press' or 'slide', got {load!r}")
    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    interface = (f'vertices in (y > {HEIGHT - TOL}) & (y < {HEIGHT + TOL})')
    upper_side, lower_side = 'Gamma_upper', 'Gamma_lower'

    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'bodies': [(E0, nu0), (E1, nu1)], 'plane': plane, 'delta': delta,
        'slave': slave, 'load': load, 'shift': float(shift),
        'steps_normal': int(steps_normal), 'steps_shear': int(steps_shear),
        'regions_slave_master': ((upper_side, lower_side) if slave == 'upper'
                                 else (lower_side, upper_side)),
    }

    regions = {
        'Omega': 'all',
        'Lower': 'cells of group 1',
        'Upper': 'cells of group 2',
        'Interface': (interface, 'facet'),
        # the interface facets of each block (the bodies share no node)
        upper_side: ('r.Interface *v r.Upper', 'facet'),
        lower_side: ('r.Interface *v r.Lower', 'facet'),
        'Bottom': (f'vertices in (y < {TOL})', 'facet'),
        'Top': (f'vertices in (y > {2 * HEIGHT - TOL})', 'facet'),
        'Pins': (f'vertices in (x < {TOL}) & ((y < {TOL}) | '
                 f'(y > {2 * HEIGHT - TOL}))', 'vertex'),
    }

    materials = {
        'solid': ({'D': {
            'Lower': stiffness_from_youngpoisson(2, E0, nu0, plane=plane),
            'Upper': stiffness_from_youngpoisson(2, E1, nu1, plane=plane)}},),
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
            'bottom': ('Bottom', {'u.1': 0.0}),
            'pins': ('Pins', {'u.0': 0.0}),
            'pressed': ('Top', {'u.1': -delta}),
        }
    else:  # the upper block dragged over the clamped lower one
        ebcs = {
            'bottom': ('Bottom', {'u.all': 0.0}),
            'moved': ('Top', {'u.0': shift, 'u.1': -delta}),
        }

    integrals = {'i': 2}

    equations = {
        'balance_of_forces': """dw_lin_elastic.i.Omega(solid.D, v, u) = 0""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6,
                                  'eps_r': 1e-12}),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
