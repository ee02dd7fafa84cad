r"""
Cattaneo–Mindlin sphere: the Hertz sphere pressed onto a rigid plane, then
sheared (issue 18's check; the 3D counterpart of ``cattaneo_mindlin.py``).

The body :math:`\Omega` is the half y ≥ 0 of the lower half-ball of radius
R centred at (0, 0, R): :math:`x^2 + y^2 + (z - R)^2 \le R^2`, y ≥ 0,
z ≤ R (``meshes/hertz_sphere.py --a 0.1 --half``, refined for a = 0.1 R).
It touches the rigid plane z = 0 (``{"kind": "plane", "point": [0, 0, 0],
"normal": [0, 0, 1]}``) at the origin. Only y = 0 is a symmetry plane (u_y = 0 there): the tangential
load along x keeps the mirror symmetry about y = 0 but breaks that about
x = 0. The contact nodes on y = 0 are rollers (their friction traction
lives in the free tangent, along x: ``solver.contact.friction.driver``).

The flat top z = R is clamped and moved in two **load stages**, exported
as a load path (``load_path*`` keys, docs/npz-format.md):

1. *normal*: the top goes down to u = (0, 0, −δ), frictionless
   (``load_path_friction`` = 0), ``steps_normal`` steps: Hertz's contact,
   radius a = (3PR/(4E*))^(1/3);
2. *shear*: the top moves sideways to u = (δ_x, 0, −δ) with friction f_c
   (the coefficient is given to the solver), ``steps_shear`` steps.

The normal load P and the tangential load Q of the whole sphere are twice
the resultants of the half's contact forces, known after the solve (equal
to the top's reactions). Cattaneo and Mindlin's solution for Q < f_c P
(Johnson, *Contact Mechanics*, 1985, §7.1): a central stick circle of
radius :math:`c = a(1 - Q/(f_c P))^{1/3}`, slip in the annulus c < r < a.
It neglects the normal–tangential coupling, which an elastic sphere on a
rigid plane has (Dundurs β ≠ 0 unless ν = 0.5): the stick zone may shift
along x (in 2D, ``cattaneo_mindlin.py``, by 5.7 % of a; here it stayed
within the node scatter) and c is expected within ~10 % (Munisamy, Hills
& Nowell 1994, for β ≠ 0).

Find :math:`\ul{u}` such that

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

with :math:`\ul{u} = (\delta_x, 0, -\delta)` on the top (the final stage)
and u_y = 0 on y = 0. SfePy solves nothing here (3D: ``_export.NO_SOLVE``,
as ``hertz_sphere.py``); the load vector of each stage is the lifting
:math:`-(K_{full} \ul{u}_D)_F` of its Dirichlet values. Clamping the top
in x removes the rigid sliding (K positive definite without contact).

Defaults: R = 1, E = 2e5, ν = 0.3, δ = 0.0095 (a ≈ 0.1 R, the load
``hertz_sphere.py`` had for its a = 0.1 R meshes), δ_x = ``delta_x`` =
2.7e-3, which gives Q/(f_c P) = 0.493 for f_c = 0.5 on
``meshes/hertz_sphere_half_6.mesh`` (a/h = 6.1; P = 298.8, a = 0.1007);
Γc the spherical facets below z = ``gamma_c_z`` · R = 0.015 R (a cap of
radius ≈ 1.7 a) minus those on y = 0. Measured there (φ_min, lagged
Coulomb; ``tests/test_cattaneo_mindlin_sphere.py``, which says how c is
estimated): c +1.2 % from CM's (the stick indicator) and +0.2 % (the stick
area), the stick circle's centre within 0.2 % of a of the axis, with
5 + 10 steps (35 s) and with 1 + 5 (16 s) alike.

Usage (from the repository root)::

  python meshes/hertz_sphere.py --a-over-h 6 --a 0.1 --half \
      -o meshes/hertz_sphere_half_6.mesh
  sfepy-run sfepy_problems/cattaneo_mindlin_sphere.py \
      -d "mesh='meshes/hertz_sphere_half_6.mesh', output='output/cm_sphere.npz'"
  python -m solver output/cm_sphere.npz --friction 0.5 \
      --formulation projection --method min

The export prints one line, ``exported 5444 DOFs, 203 contact nodes ->
PATH``. Parameters (``-d``): ``mesh``, ``output``, ``E``, ``nu``, ``R``
(must be the mesh's radius), ``delta``, ``delta_x``, ``gamma_c_z``,
``a_target``, ``steps_normal`` (5), ``steps_shear`` (10), ``verbose``.
"""
import importlib.util
import os.path as op
import sys

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates, relative to R.
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


def _export():
    return _load('_contact_ssn_sfepy_export', '_export.py')


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M and the two load stages."""
    conf = pb.conf.options
    sphere = _load('_contact_ssn_hertz_sphere', 'hertz_sphere.py')
    R, coors = conf.R, pb.domain.mesh.coors
    radius = ((coors - [0, 0, R]) ** 2).sum(axis=1).max() ** 0.5
    if abs(radius - R) > 1e-6 * R:
        raise ValueError(f'the mesh has radius {radius:g}, but R = {R:g}: '
                         'pass R=... with -d, or another mesh')
    export = _export()
    cells = pb.domain.mesh.get_conn('3_4').astype('int64')
    h = sphere.contact_size(coors, export.contact_triangles(
        pb, 'Gamma_c', cells, coors), conf.a_target)
    stages = [dict(dirichlet=(0.0, 1.0, 1.0), load=0.0,
                   steps=conf.steps_normal, friction=0.0),
              dict(dirichlet=(1.0, 1.0, 1.0), load=0.0,
                   steps=conf.steps_shear, friction=1.0)]
    return export.export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle={'kind': 'plane', 'point': [0.0, 0.0, 0.0],
                  'normal': [0.0, 0.0, 1.0]}, load_path=stages,
        meta={'E': conf.E, 'nu': conf.nu, 'R': R, 'delta': conf.delta,
              'delta_x': conf.delta_x,
              'E_star': conf.E / (1.0 - conf.nu ** 2),
              'a_target': conf.a_target, 'h_contact': h,
              'a_h': conf.a_target / h, 'half': True,
              'contact_center': [0.0, 0.0, 0.0],
              'load': {'stages': ['normal: top to (0, 0, -delta), '
                                  'frictionless',
                                  'shear: top to (delta_x, 0, -delta), '
                                  'friction'],
                       'on': 'top z = R (clamped, moved)'},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/cattaneo_mindlin_sphere.py',
              'description': 'Cattaneo-Mindlin: half sphere '
                             '|x - (0,0,R)| <= R, y >= 0, z <= R on the '
                             'rigid plane z = 0, pressed, then sheared '
                             'along x',
              'supports': 'top z = R: u = (delta_x, 0, -delta); u_y = 0 '
                          'on y = 0',
              'contact_boundary': f'sphere below z = {conf.gamma_c_z:g} R',
              'cattaneo_mindlin': 'P, Q = 2 * the resultants of the '
                                  'contact forces (the whole sphere); '
                                  'c = a (1 - Q / (f_c P))^(1/3)'})


def define(mesh='meshes/hertz_sphere_half_6.mesh',
           output='output/cm_sphere.npz', E=2e5, nu=0.3, R=1.0,
           delta=0.0095, delta_x=2.7e-3, gamma_c_z=0.015, a_target=None,
           steps_normal=5, steps_shear=10, verbose=None):
    _export().set_verbosity(verbose)  # before SfePy's 'left over:'

    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': False,  # SfePy solves nothing (NO_SOLVE)
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'R': R, 'delta': delta, 'delta_x': delta_x,
        'gamma_c_z': gamma_c_z,
        'a_target': 0.1 * R if a_target is None else a_target,
        'steps_normal': int(steps_normal), 'steps_shear': int(steps_shear),
    }

    tol = TOL * R
    regions = {
        'Omega': 'all',
        'Top': (f'vertices in (z > {R - tol})', 'facet'),
        'Y0': (f'vertices in (y < {tol})', 'facet'),
        'Surface': ('vertices of surface', 'facet'),
        'Low': (f'vertices in (z < {gamma_c_z * R + tol})', 'facet'),
        # Spherical facets below z = gamma_c_z R, minus those on y = 0
        # (facet set operations; parentheses: SfePy groups from the right).
        'Gamma_c': ('(r.Surface *s r.Low) -s r.Y0', 'facet'),
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(3, E, nu)},),
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
        'moved': ('Top', {'u.0': delta_x, 'u.1': 0.0, 'u.2': -delta}),
        'symmetry_y': ('Y0', {'u.1': 0.0}),
    }

    integrals = {
        'i': 2,
    }

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u) = 0""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(_export().NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_export().main(__file__))
