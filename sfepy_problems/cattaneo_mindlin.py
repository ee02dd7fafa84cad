r"""
Cattaneo–Mindlin partial slip: the Hertz half-cylinder, then sheared.

The body, mesh and obstacle of ``hertz_cylinder.py`` (the half-disk of
radius R below y = 0 on the rigid line y = -R), with the whole flat top edge
moved as a rigid clamp in two **load stages**, exported as a load path in
the ``.npz`` (``load_path*`` keys, docs/npz-format.md):

1. *normal*: the top goes down to u = (0, -d), frictionless
   (``load_path_friction`` = 0), ``steps_normal`` steps — Hertz's contact;
2. *shear*: the top moves sideways to u = (δ, -d) with friction f_c (the
   coefficient is given to the solver), ``steps_shear`` steps.

The tangential load Q and the normal load P (per unit length) are the
resultants of the contact forces, known after the solve. Cattaneo and
Mindlin's solution for Q < f_c P: a central stick zone of half-width
:math:`c = a\sqrt{1 - Q/(f_c P)}`, slip outside it. It assumes no coupling
of normal and tangential tractions, which an elastic body on a rigid
obstacle has unless ν = 0.5: expect the stick zone shifted by a few per cent
of a and its half-length close to c (``notebooks/verification.ipynb``).

Find :math:`\ul{u}` such that:

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

with :math:`\ul{u} = (\delta, -d)` on the top edge y = 0 (the final stage;
SfePy solves only this problem without contact). The exported load vector
of each stage is the lifting :math:`-(K_{full} \ul{u}_D)_F` of its Dirichlet
values.

Usage examples::

  python sfepy_problems/cattaneo_mindlin.py \
      -d "mesh='meshes/hertz.mesh', output='output/cm.npz'"
  python -m solver output/cm.npz --friction 0.5 --formulation projection \
      --method min --plots

The export prints one line, ``exported 7106 DOFs, 109 contact nodes ->
/.../output/cm.npz``; ``-v`` shows SfePy's messages. ``sfepy-run
sfepy_problems/cattaneo_mindlin.py -d "..."`` does the same (with
``verbose=True`` in ``-d`` for SfePy's messages; see ``block_obstacle.py``).
The solve needs the friction coefficient, ``--friction``: the ``.npz``
carries only the load path.

Parameters of ``define()`` (``-d``): ``mesh``, ``output`` (the ``.npz``;
SfePy's solution without contact goes in the same folder as ``.vtk``, named
after the mesh, so ``hertz.vtk`` as for ``hertz_cylinder.py``), ``E``,
``nu``, ``plane``, ``d`` (0.016), ``delta`` (the sideways motion of the top,
default 7e-3, which gives Q/(f_c P) ≈ 0.5 for f_c = 0.5), ``R``,
``gamma_c_y``, ``steps_normal`` (10), ``steps_shear`` (20), ``order``,
``verbose`` and ``solve`` (True: SfePy also solves the unconstrained problem and writes
its ``.vtk``, a check; False: export only, ``_export.NO_SOLVE``, see
``block_obstacle.py``).
"""
import importlib.util
import os.path as op
import sys

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

TOL = 1e-8


def _load(name, filename):
    """A sibling file of this folder by path (it is not a package)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, op.join(op.dirname(op.abspath(__file__)), filename))
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M and the two load stages."""
    conf = pb.conf.options
    E_star = conf.E / (1.0 - conf.nu ** 2) if conf.plane == 'strain' \
        else conf.E
    stages = [dict(dirichlet=(0.0, 1.0), load=0.0, steps=conf.steps_normal,
                   friction=0.0),
              dict(dirichlet=(1.0, 1.0), load=0.0, steps=conf.steps_shear,
                   friction=1.0)]
    _load('_contact_ssn_sfepy_export', '_export.py').export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=conf.obstacle, load_path=stages,
        meta={'E': conf.E, 'nu': conf.nu, 'plane': conf.plane,
              'R': conf.R, 'd': conf.d, 'delta': conf.delta,
              'E_star': E_star,
              'load': {'stages': ['normal: top to (0, -d), frictionless',
                                  'shear: top to (delta, -d), friction'],
                       'on': 'top edge y = 0 (clamped, moved)'},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/cattaneo_mindlin.py',
              'description': 'Cattaneo-Mindlin: Hertz half-cylinder, then '
                             'sheared by moving its top sideways',
              'supports': 'top edge y = 0: u = (delta, -d)',
              'contact_boundary': f'arc y < {conf.gamma_c_y:g} R'})


def define(mesh='meshes/hertz.mesh', output='output/cm.npz', E=2e5, nu=0.3,
           plane='strain', d=0.016, delta=7e-3, R=1.0, gamma_c_y=-0.8,
           steps_normal=10, steps_shear=20, order=1, solve=True,
           verbose=None):
    export = _load('_contact_ssn_sfepy_export', '_export.py')
    export.set_verbosity(verbose)
    from solver.geometry.curves.parametric import ParametricCurve

    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    obstacle_y = repr(-float(R))
    if obstacle_y.endswith('.0'):
        obstacle_y = obstacle_y[:-2]

    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': bool(solve),  # no solve: no .vtk of a zero field
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'plane': plane, 'd': d, 'delta': delta, 'R': R,
        'gamma_c_y': gamma_c_y, 'steps_normal': int(steps_normal),
        'steps_shear': int(steps_shear),
        'obstacle': ParametricCurve('t', obstacle_y),
    }

    tol = TOL * R
    regions = {
        'Omega': 'all',
        'Top': (f'vertices in (y > {-tol})', 'facet'),
        'Surface': ('vertices of surface', 'facet'),
        'Low': (f'vertices in (y < {gamma_c_y * R + tol})', 'facet'),
        'Gamma_c': ('r.Surface *e r.Low', 'facet'),
    }
    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(2, E, nu,
                                                    plane=plane)},),
    }
    fields = {
        'displacement': ('real', 'vector', 'Omega', order),
        'scalar': ('real', 'scalar', 'Omega', 1),
    }
    variables = {
        'u': ('unknown field', 'displacement', 0),
        'v': ('test field', 'displacement', 'u'),
        'p': ('unknown field', 'scalar', 1),
        'q': ('test field', 'scalar', 'p'),
    }
    ebcs = {
        'moved': ('Top', {'u.0': delta, 'u.1': -d}),
    }
    integrals = {'i': 2 * order}
    equations = {
        'balance_of_forces': """dw_lin_elastic.i.Omega(solid.D, v, u) = 0""",
    }
    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6,
                                  'eps_r': 1e-12} if solve
                   else dict(export.NO_SOLVE)),
    }
    return locals()


if __name__ == '__main__':
    sys.exit(_load('_contact_ssn_sfepy_export', '_export.py').main(__file__))
