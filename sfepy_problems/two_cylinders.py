r"""
Hertz (and Cattaneo–Mindlin) contact of two elastic cylinders.

Exports a two-body problem (``.npz`` format version 4, issue 19;
``docs/npz-format.md``) for the dual mortar contact solver: two half-discs
touching at the origin, meshed in one file with a cell group per body
(``meshes/two_body_cylinders.mesh``, made by ``meshes/two_body.py``):

* body 1, the **upper** half-disc of radius R1 centred at (0, R1), flat
  side y = R1 on top, E1, ν1 — the **slave** (its arc below y = 0.2 R1,
  element size 0.004 R1 at the contact point);
* body 0, the **lower** half-disc of radius R2 centred at (0, −R2), flat
  side y = −R2 at the bottom, E2, ν2 — the **master** (its arc above y =
  −0.2 R2, size 0.006 there).

SfePy builds K (block-diagonal), f and the slave boundary matrix M; it
solves only the elasticity problem without contact. Find :math:`\ul{u}`
with :math:`\sum_b \int_{\Omega_b} D^b_{ijkl} e_{ij}(\ul{v}) e_{kl}(\ul{u})
= 0` for all :math:`\ul{v}`, plane strain (or stress), the lower flat side
clamped and the upper flat side moved down by δ.

**A displacement (default) or a force.** With ``load='hertz'`` the upper
cylinder is loaded through the prescribed displacement of its flat side
(u_y = −δ; u_x = 0 only at its centre (0, R1), so the side may expand);
the force per unit length P is the top reaction, known after the contact
solve (``meta['P_estimate']`` is an estimate, below). With
``load='force'`` the flat side carries P (default ``P_estimate``) as a
uniform traction and the upper cylinder is held vertically by the contact
only (K singular, solved exactly: README "Loads"). u_x = 0 at its centre
(0, R1) and at its apex (0, 0) hold the horizontal translation and the
rotation: both points lie on the axis of symmetry, where u_x = 0 holds in
the symmetric problem, and the rotation about the circle's centre is one
that frictionless contact with a round surface does not resist (only the
polygon's facets would, weakly).

**Hertz** (two cylinders, plane strain): 1/R* = 1/R1 + 1/R2, 1/E* =
(1 − ν1²)/E1 + (1 − ν2²)/E2, half-width a = 2√(P R*/(π E*)), peak pressure
p0 = 2P/(π a). The default δ (``delta=None``) aims at a = ``a_target``
(0.1 R1): P from Hertz's a, and δ = Σ_b P (1 − ν_b²)/(π E_b) (2 ln(4 R_b/a)
− 1), the approach of a half-disc of height R_b pressed by a Hertz
pressure (this reproduces ``hertz_cylinder.py``: P = 1739.6 at d = 0.016
gives 0.0161). With the default meshes about 50 slave nodes then lie in
the contact zone (≥ 40 asked by issue 19). Defaults: R1 = 1, R2 = 1.5,
E1 = 2e5, ν1 = 0.3, E2 = 1.2e5, ν2 = 0.25.

**Cattaneo–Mindlin** (``load='cattaneo'``, use ``identical=True``: Dundurs
β = 0, so the classical solution is exact): the upper flat side is clamped
and moved in two load stages (``load_path_*`` keys): (1) to (0, −δ),
frictionless, ``steps_normal`` steps; (2) to (``shift``, −δ) with friction
f_c (given to the solver), ``steps_shear`` steps. Stick half-width c =
a√(1 − Q/(f_c P)), Q the tangential reaction. The default shift (0.44 δ)
gives Q/(f_c P) ≈ 0.5 for f_c = 0.5 (twice the tangential compliance of
``cattaneo_mindlin.py``'s half-cylinder on a rigid flat).

Usage::

  python meshes/two_body.py cylinders      # the meshes, if absent
  python meshes/two_body.py cylinders --identical
  sfepy-run sfepy_problems/two_cylinders.py \
      -d "mesh='meshes/two_body_cylinders.mesh', output='output/two_cylinders.npz'"
  sfepy-run sfepy_problems/two_cylinders.py \
      -d "mesh='meshes/two_body_cylinders_identical.mesh', output='output/two_cylinders_cm.npz', identical=True, load='cattaneo'"
  python -m solver output/two_cylinders.npz
  python -m solver output/two_cylinders_cm.npz --friction 0.5 --formulation projection

(``python sfepy_problems/two_cylinders.py -d "..."`` is the same, quiet:
``_export.py``.)

Parameters (``-d``): ``mesh``, ``output``, ``R1``, ``R2``, ``E1``, ``nu1``,
``E2``, ``nu2``, ``identical`` (False: R2, E2, ν2 = R1, E1, ν1; needs the
identical mesh), ``plane`` ('strain'), ``delta`` (None: from
``a_target``), ``a_target`` (0.1 R1), ``load`` ('hertz' or 'cattaneo'),
``P`` (``load='force'``: the force per unit length; None:
``P_estimate``), ``shift`` (None: 0.44 δ), ``steps_normal`` (10), ``steps_shear`` (20),
``gamma_c_y`` (0.2: the slave arc is below y = gamma_c_y R1, the master
arc above y = −gamma_c_y R2), ``verbose``.
"""
import importlib.util
import math
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates, relative to the radii.
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


def hertz(R1, R2, E1, nu1, E2, nu2, plane='strain'):
    """(R*, E*) of two cylinders (plane stress: E* from E alone)."""
    c1 = (1 - nu1 ** 2) / E1 if plane == 'strain' else 1 / E1
    c2 = (1 - nu2 ** 2) / E2 if plane == 'strain' else 1 / E2
    return 1 / (1 / R1 + 1 / R2), 1 / (c1 + c2)


def approach(P, a, bodies, plane='strain'):
    """δ = Σ_b P c_b/π (2 ln(4 R_b/a) − 1), c_b = (1 − ν_b²)/E_b: the
    approach of half-discs of height R_b under a Hertz pressure of
    half-width a (an estimate; see the module doc)."""
    total = 0.0
    for R, E, nu in bodies:
        c = (1 - nu ** 2) / E if plane == 'strain' else 1 / E
        total += P * c / math.pi * (2 * math.log(4 * R / a) - 1)
    return total


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: K, f, M, the interface (and stages)."""
    conf = pb.conf.options
    coors = pb.domain.mesh.coors
    for name, R, centre, body in (('R1', conf.R1, conf.R1, 'Upper'),
                                  ('R2', conf.R2, -conf.R2, 'Lower')):
        xy = coors[pb.domain.regions[body].vertices]
        radius = nm.hypot(xy[:, 0], xy[:, 1] - centre).max()
        if abs(radius - R) > 1e-6 * R:
            raise ValueError(f'the mesh has {name} = {radius:g}, but {name} '
                             f'= {R:g}: pass {name}=... (or identical=True) '
                             'with -d, or another mesh')
    stages = None
    if conf.load == 'cattaneo':
        stages = [dict(dirichlet=(0.0, 1.0), load=0.0,
                       steps=conf.steps_normal, friction=0.0),
                  dict(dirichlet=(1.0, 1.0), load=0.0,
                       steps=conf.steps_shear, friction=1.0)]
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load=('dw_surface_ltr.i.Top(load.val, v)' if conf.load == 'force'
              else None),
        obstacle=None, load_path=stages,
        mortar=dict(slave='Gamma_s', master='Gamma_m',
                    bodies=['Lower', 'Upper']),
        meta=conf.meta | {'mesh': op.basename(pb.conf.filename_mesh)})


def define(mesh='meshes/two_body_cylinders.mesh',
           output='output/two_cylinders.npz', R1=1.0, R2=1.5, E1=2e5,
           nu1=0.3, E2=1.2e5, nu2=0.25, identical=False, plane='strain',
           delta=None, a_target=None, load='hertz', shift=None,
           steps_normal=10, steps_shear=20, gamma_c_y=0.2, P=None,
           verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    if load not in ('hertz', 'cattaneo', 'force'):
        raise ValueError(f"load must be 'hertz', 'cattaneo' or 'force', got "
                         f"{load!r}")
    if identical:
        R2, E2, nu2 = R1, E1, nu1
    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    R_star, E_star = hertz(R1, R2, E1, nu1, E2, nu2, plane)
    a = 0.1 * R1 if a_target is None else float(a_target)
    P_estimate = math.pi * E_star * a ** 2 / (4 * R_star)  # Hertz's a
    if delta is None:
        delta = approach(P_estimate, a, [(R1, E1, nu1), (R2, E2, nu2)],
                         plane)
    if shift is None:
        shift = 0.44 * delta
    delta, shift = float(delta), float(shift)
    force = None
    if load == 'force':
        force = P if P is not None else P_estimate
        if not (isinstance(force, (int, float)) and math.isfinite(force)
                and force > 0):
            raise ValueError(f'P must be a positive number, got {P!r}')
        force = float(force)

    meta = {
        'E': E1, 'nu': nu1, 'plane': plane,
        'bodies': [{'name': 'lower cylinder', 'E': E2, 'nu': nu2},
                   {'name': 'upper cylinder', 'E': E1, 'nu': nu1}],
        'slave_body': 1, 'master_body': 0,
        'R1': R1, 'R2': R2, 'E1': E1, 'nu1': nu1, 'E2': E2, 'nu2': nu2,
        'R_star': R_star, 'E_star': E_star, 'delta': delta,
        'a_target': a, 'P_estimate': P_estimate, 'identical': bool(identical),
        'load': ({'prescribed_displacement_y': -delta,
                  'on': 'upper flat side y = R1',
                  'u_x_pinned_at': [0.0, R1]} if load == 'hertz' else
                 {'force_y': -force, 'on': 'upper flat side y = R1, '
                  'uniform traction', 'u_x_pinned_at': [[0.0, R1],
                                                        [0.0, 0.0]]}
                 if load == 'force' else
                 {'stages': ['normal: upper flat side to (0, -delta), '
                             'frictionless',
                             'shear: to (shift, -delta), friction'],
                  'shift': shift, 'on': 'upper flat side y = R1 (clamped)'}),
        'problem_file': 'sfepy_problems/two_cylinders.py',
        'description': 'two cylinders: upper half-disc (R1, slave) on '
                       'lower half-disc (R2, master), touching at (0, 0)',
        'supports': 'lower flat side y = -R2 clamped; upper flat side y = '
                    'R1 prescribed',
        'contact_boundary': f'slave: upper arc y < {gamma_c_y:g} R1; master: '
                            f'lower arc y > -{gamma_c_y:g} R2',
        'hertz': 'a = 2 sqrt(P R_star / (pi E_star)), p0 = 2 P / (pi a), '
                 'P = the reaction on the upper flat side' if load != 'force'
                 else 'a = 2 sqrt(P R_star / (pi E_star)), p0 = 2 P / (pi a), '
                 'P given',
    }
    if load == 'force':
        meta['P'] = force
        meta['supports'] = ('lower flat side y = -R2 clamped; upper '
                            'cylinder: u_x = 0 at (0, R1) and (0, 0), held '
                            'in y by the contact only')
    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'R1': R1, 'R2': R2, 'load': load, 'meta': meta,
        'steps_normal': int(steps_normal), 'steps_shear': int(steps_shear),
    }

    tol1, tol2 = TOL * R1, TOL * R2
    regions = {
        'Omega': 'all',
        'Lower': 'cells of group 1',
        'Upper': 'cells of group 2',
        'Surface': ('vertices of surface', 'facet'),
        'BandU': (f'vertices in (y < {gamma_c_y * R1 + tol1})', 'facet'),
        'BandL': (f'vertices in (y > {-gamma_c_y * R2 - tol2})', 'facet'),
        'NearU': ('r.BandU *v r.Upper', 'facet'),
        'NearL': ('r.BandL *v r.Lower', 'facet'),
        'Gamma_s': ('r.Surface *e r.NearU', 'facet'),
        'Gamma_m': ('r.Surface *e r.NearL', 'facet'),
        'Top': (f'vertices in (y > {R1 - tol1})', 'facet'),
        'TopCentre': (f'vertices in (y > {R1 - tol1}) & (x > {-tol1}) & '
                      f'(x < {tol1})', 'vertex'),
        'Bottom': (f'vertices in (y < {-R2 + tol2})', 'facet'),
        'Origin': (f'vertices in (x > {-tol1}) & (x < {tol1}) & '
                   f'(y > {-tol1}) & (y < {tol1})', 'vertex'),
        'Apex': ('r.Origin *v r.Upper', 'vertex'),
    }

    materials = {
        'solid': ({'D': {
            'Lower': stiffness_from_youngpoisson(2, E2, nu2, plane=plane),
            'Upper': stiffness_from_youngpoisson(2, E1, nu1, plane=plane)}},),
        # load='force': P per unit length, uniform on the flat side (2 R1)
        'load': ({'val': nm.array([[0.0],
                                   [-(force or 0.0) / (2.0 * R1)]])},),
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

    ebcs = {'clamped': ('Bottom', {'u.all': 0.0})}
    if load == 'hertz':
        ebcs.update(pressed=('Top', {'u.1': -delta}),
                    pinned=('TopCentre', {'u.0': 0.0}))
    elif load == 'force':  # held in y by the contact only
        ebcs.update(pinned=('TopCentre', {'u.0': 0.0}),
                    apex=('Apex', {'u.0': 0.0}))
    else:
        ebcs.update(moved=('Top', {'u.0': shift, 'u.1': -delta}))

    integrals = {'i': 2}

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u) = 0""" if load != 'force'
        else """dw_lin_elastic.i.Omega(solid.D, v, u)
              = dw_surface_ltr.i.Top(load.val, v)""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        # K is singular under a force (no support in y): SfePy solves nothing
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6,
                                  'eps_r': 1e-12} if load != 'force'
                   else dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
