r"""
Two elastic spheres in contact (3D, dual mortar on triangles): Hertz, and
Cattaneo–Mindlin for two identical spheres pressed then sheared.

Exports a 3D two-body problem (``.npz`` format version 4 on tetrahedra,
``docs/npz-format.md``) for the contact solver: body 0, the slave, is the
lower half-ball of radius R₀ centred at (0, 0, R₀) (E₀, ν₀); body 1, the
master, the upper half-ball of radius R₁ centred at (0, 0, −R₁) (E₁, ν₁);
they touch at the origin. The mesh (``meshes/two_spheres.py``) holds their
quarters x, y ≥ 0 (symmetry planes x = 0 and y = 0) or, for the shear, their
halves y ≥ 0 (symmetry plane y = 0). SfePy assembles K (block-diagonal), f
and the slave boundary matrix and solves nothing (3D: ``_export.NO_SOLVE``);
the contact solver computes the mortar matrices and solves.

Find :math:`\ul{u}` such that

.. math::
    \sum_{b=0,1} \int_{\Omega_b} D^b_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    = 0 \;, \quad \forall \ul{v} \;,

with u = 0 on the master's flat bottom z = −R₁, u_z = −δ on the slave's flat
top z = R₀ (``load='press'``; on a half mesh also u_x = 0 there, which
removes the rigid sliding along x), u_x = 0 on x = 0 and u_y = 0 on y = 0
(the symmetry planes; interface nodes there are rollers). The force of the
whole pair is P = 4 × (2 × on a half mesh) the interface normal force of the
model (``summary.json``'s ``interface_normal_force``). Hertz (Johnson,
*Contact Mechanics*, §4.2): 1/R* = 1/R₀ + 1/R₁, 1/E* = (1 − ν₀²)/E₀ + (1 −
ν₁²)/E₁, a = (3PR*/(4E*))^{1/3}, p₀ = 3P/(2πa²).

``load='cattaneo'`` (a half mesh, identical spheres: ``R1=R0, E1=E0,
nu1=nu0``): the top is clamped and moved in two load stages (a load path):
(1) to (0, 0, −δ), frictionless, ``steps_normal`` steps; (2) to (``shift``,
0, −δ) with friction f_c (given to the solver), ``steps_shear`` steps.
Identical spheres have Dundurs' β = 0: the normal and tangential problems
uncouple, and Cattaneo and Mindlin's stick radius c = a(1 − Q/(f_c P))^{1/3}
holds for the total tangential force Q < f_c P (Johnson §7.1).

Interface: the slave's spherical facets within ``cap`` of the axis (default
4 a_target) minus those on the symmetry planes; the master's within 1.25 ×
``cap`` (it covers the slave). Small deformation and small sliding: the
mortar integrals are computed once, on the undeformed surfaces.

Usage (from the repository root)::

  python meshes/two_spheres.py --a-over-h 6 -o meshes/two_spheres_6.mesh
  sfepy-run sfepy_problems/two_spheres.py \
      -d "mesh='meshes/two_spheres_6.mesh', output='output/two_spheres_6.npz'"
  python -m solver output/two_spheres_6.npz --plots

**A sphere on a box** (``master='box'``, a mesh of ``meshes/two_spheres.py
--box``): the master is the box [0, R₀]² × [−R₀, 0], its top z = 0 the
master surface, its bottom clamped; ``E_ratio`` sets E1 = E_ratio × E0.
As E1 grows the run tends to the sphere on the rigid plane
(``hertz_sphere.py`` on the same sphere mesh): the rigid limit.

Parameters (``-d``): ``mesh``, ``output``, ``E0`` (2e5), ``nu0`` (0.3),
``E1`` (1e5), ``nu1`` (0.25), ``R0`` (1), ``R1`` (1.5) (the mesh's radii),
``delta`` (0.0041: a ≈ 0.05 R₀ for the defaults), ``a_target`` (0.05 R₀,
the contact radius the mesh is refined for), ``cap``, ``load`` ('press' or
'cattaneo'), ``shift`` (1e-3), ``steps_normal`` (1), ``steps_shear`` (5),
``master`` ('sphere' or 'box'), ``E_ratio``, ``verbose``.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates, relative to R₀.
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


def _load_export():
    return _load('_contact_ssn_sfepy_export', '_export.py')


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M, the interface, the load."""
    conf = pb.conf.options
    export = _load_export()
    coors = pb.domain.mesh.coors
    cells = pb.domain.mesh.get_conn('3_4').astype(nm.int64)
    slave = export.contact_triangles(pb, 'Gamma_s', cells, coors)
    sphere = _load('_contact_ssn_hertz_sphere', 'hertz_sphere.py')
    h = sphere.contact_size(coors, slave, conf.a_target)
    fraction = 0.5 if conf.half else 0.25
    stages, load = None, {'prescribed_displacement_z': -conf.delta,
                          'on': 'slave top z = R0'}
    if conf.load == 'cattaneo':
        stages = [dict(dirichlet=(0.0, 1.0, 1.0), load=0.0,
                       steps=conf.steps_normal, friction=0.0),
                  dict(dirichlet=(1.0, 1.0, 1.0), load=0.0,
                       steps=conf.steps_shear, friction=1.0)]
        load = {'stages': ['normal: top to (0, 0, -delta), frictionless',
                           'shear: top to (shift, 0, -delta), friction'],
                'shift': conf.shift, 'on': 'slave top z = R0 (clamped)'}
    (E0, nu0), (E1, nu1) = conf.bodies
    box = conf.master == 'box'
    radii = [conf.R0] if box else [conf.R0, conf.R1]
    return export.export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=None, load_path=stages,
        mortar=dict(slave='Gamma_s', master='Gamma_m',
                    bodies=['Upper', 'Lower']),
        meta={'E': E0, 'nu': nu0,
              'bodies': [{'name': 'upper sphere (slave)', 'E': E0,
                          'nu': nu0},
                         {'name': ('box (master)' if box else
                                   'lower sphere (master)'), 'E': E1,
                          'nu': nu1}],
              'slave_body': 0, 'master_body': 1,
              'radii': radii, 'delta': conf.delta,
              'a_target': conf.a_target, 'h_contact': h,
              'a_h': conf.a_target / h, 'fraction': fraction,
              'contact_center': [0.0, 0.0, 0.0],
              'contact_axis': [0.0, 0.0, 1.0],
              'load': load, 'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/two_spheres.py',
              'description': ('an elastic sphere on an elastic box'
                              if box else 'two elastic spheres')
              + ' touching at the origin '
              f'({"half" if conf.half else "quarter"} model)',
              'supports': 'master bottom z = -R1 clamped; slave top z = R0 '
                          'moved; symmetry planes',
              'hertz': 'P = interface normal force / fraction; 1/R* = '
                       '1/R0 + 1/R1, 1/E* = sum (1 - nu^2)/E, a = (3 P R* '
                       '/ (4 E*))^(1/3), p0 = 3 P / (2 pi a^2)'},
    )


def define(mesh='meshes/two_spheres_6.mesh',
           output='output/two_spheres.npz', E0=2e5, nu0=0.3, E1=1e5,
           nu1=0.25, R0=1.0, R1=1.5, delta=0.0041, a_target=None, cap=None,
           load='press', shift=1e-3, steps_normal=1, steps_shear=5,
           master='sphere', E_ratio=None, verbose=None):
    import meshio

    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    if load not in ('press', 'cattaneo'):
        raise ValueError(f"load must be 'press' or 'cattaneo', got {load!r}")
    if master not in ('sphere', 'box'):
        raise ValueError(f"master must be 'sphere' or 'box', got "
                         f"{master!r}")
    if E_ratio is not None:
        E1 = E_ratio * E0
    depth = R0 if master == 'box' else R1  # of the master's flat bottom
    filename_mesh = op.abspath(mesh)
    points = meshio.read(filename_mesh).points
    tol = TOL * R0
    half = bool(points[:, 0].min() < -tol)
    if load == 'cattaneo' and not half:
        raise ValueError("load='cattaneo' shears along x: it needs a half "
                         "mesh (meshes/two_spheres.py --half)")
    a_target = 0.05 * R0 if a_target is None else a_target
    cap = 4 * a_target if cap is None else cap
    output_dir = op.dirname(op.abspath(output))
    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': False,  # SfePy solves nothing (NO_SOLVE)
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output), 'bodies': [(E0, nu0), (E1, nu1)],
        'R0': R0, 'R1': R1, 'delta': delta, 'a_target': a_target,
        'half': half, 'load': load, 'shift': float(shift),
        'master': master,
        'steps_normal': int(steps_normal), 'steps_shear': int(steps_shear),
    }

    symmetry = 'r.Y0' if half else '(r.X0 +s r.Y0)'

    def on_sphere(centre, radius, within):
        """The vertices on the sphere |x − (0, 0, centre)| = radius within
        ``within`` of the z axis (SfePy's ``vertices by``)."""
        def select(coors, domain=None):
            d = nm.sqrt(coors[:, 0] ** 2 + coors[:, 1] ** 2
                        + (coors[:, 2] - centre) ** 2)
            near = nm.hypot(coors[:, 0], coors[:, 1]) < within
            return nm.flatnonzero((abs(d - radius) < 1e-6 * radius) & near)
        return (select,)

    def on_plane(within):
        """The vertices on z = 0 within ``within`` of the z axis (the
        box's top)."""
        def select(coors, domain=None):
            near = nm.hypot(coors[:, 0], coors[:, 1]) < within
            return nm.flatnonzero((abs(coors[:, 2]) < 1e-9 * R0) & near)
        return (select,)

    functions = {'sphere_s': on_sphere(R0, R0, cap),
                 'sphere_m': (on_sphere(-R1, R1, 1.25 * cap)
                              if master == 'sphere'
                              else on_plane(1.25 * cap))}
    regions = {
        'Omega': 'all',
        'Upper': 'cells of group 1',
        'Lower': 'cells of group 2',
        'Surface': ('vertices of surface', 'facet'),
        'Top': (f'vertices in (z > {R0 - tol})', 'facet'),
        'Bottom': (f'vertices in (z < {-depth + tol})', 'facet'),
        'Y0': (f'vertices in (y < {tol})', 'facet'),
        # the facets with every vertex on the sphere (one touching node of
        # the other body is on it too, but none of its facets)
        'CapS': ('vertices by sphere_s', 'facet'),
        'CapM': ('vertices by sphere_m', 'facet'),
        # SfePy groups region operators from the right: parenthesise.
        'Gamma_s': (f'(r.Surface *s r.CapS) -s {symmetry}', 'facet'),
        'Gamma_m': (f'(r.Surface *s r.CapM) -s {symmetry}', 'facet'),
    }
    if not half:
        regions['X0'] = (f'vertices in (x < {tol}) & (x > {-tol})', 'facet')

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
        top = {'u.2': -delta, **({'u.0': 0.0} if half else {})}
    else:
        top = {'u.0': shift, 'u.1': 0.0, 'u.2': -delta}
    ebcs = {
        'bottom': ('Bottom', {'u.all': 0.0}),
        'pressed': ('Top', top),
        'symmetry_y': ('Y0', {'u.1': 0.0}),
        **({} if half else {'symmetry_x': ('X0', {'u.0': 0.0})}),
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
