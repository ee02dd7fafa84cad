r"""
Hertz line contact: an elastic half-cylinder pressed onto a rigid flat.

This problem file assembles and **exports** the discrete model of a contact
problem with a closed-form solution (Hertz, plane strain line contact), as
``block_obstacle.py`` does for the thesis's block: SfePy builds K, f and M,
the contact solver (``python -m solver``, which never imports SfePy) reads
them from an ``.npz`` file. SfePy itself solves only the linear elasticity
problem below *without* contact (the body then passes through the
obstacle); that solution is written as usual and checks the exported K, f.

The body :math:`\Omega` is the lower half of the disk of radius R centred at
the origin, :math:`x^2 + y^2 \le R^2,\ y \le 0`: the flat top edge
:math:`\Gamma_D` on y = 0 and a circular arc below, touching the rigid
obstacle, the line y = -R (:math:`\Gamma_o(t) = [t, -R]`), at (0, -R).

Find :math:`\ul{u}` such that:

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

with :math:`u_y = -d` on :math:`\Gamma_D` (y = 0) and :math:`u_x = 0` at the
single node (0, 0), where :math:`D_{ijkl}` is the plane strain (or plane
stress) isotropic elasticity tensor for E, ν. The exported matrices are

.. math::
    \ul{v}^T K \ul{u} = \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    \;, \quad
    f = -(K_{full}\, \ul{u}_D)_F
    \;, \quad
    M_{ij} = \int_{\Gamma_c} \varphi_i \varphi_j \;,

K reduced to the free DOFs F, f the lifting of the prescribed displacement
:math:`\ul{u}_D` (there is no other load), M over the nodes of
:math:`\Gamma_c` ordered along it (``_export.py``).

**A prescribed displacement (default) or a force** (``load='force'``). By
default the top edge is moved down by d (it stays straight and may slide
sideways; only the top centre is pinned in x to remove the horizontal
rigid motion): K is positive definite, and the total force per unit length
P is known only after the contact solve: it is the sum of the vertical
contact forces :math:`P = \sum_i \lambda_i (-\nu_{i,y})` (ν from the body
to the obstacle, here (0, -1); λ ≥ 0), equal to the reaction on the top
edge. With ``load='force'`` the top edge carries the uniform traction
-P/(2R) instead and is free in y: the vertical translation and the
rotation about (0, 0) are held by the contact only, K is singular, and the
solver balances P by the contact forces exactly (issue 31,
``solver/contact/strategies/floating.py``).

**Hertz's solution** (rigid flat, :math:`E^* = E/(1-\nu^2)` in plane strain,
:math:`E^* = E` in plane stress): half-width :math:`a = 2\sqrt{PR/(\pi E^*)}`,
peak pressure :math:`p_0 = 2P/(\pi a)`, pressure
:math:`p(x) = p_0\sqrt{1 - x^2/a^2}`. It assumes a ≪ R (a half-space). For
R = 1, E = 2e5, ν = 0.3 and d = 0.016 the contact solution on
``meshes/hertz.mesh`` has P = 1739.6, i.e. a = 0.1004 R; the half-width and
peak pressure fitted to its pressure differ from Hertz's by -0.4 % and
+0.25 %, mostly the finite size of the body, an error ≈ -0.4 (a/R)² in a
(``tests/test_hertz.py``). Measure gaps from the obstacle (``--gap
obstacle``): normals along the body's normals are not Hertz's vertical
contact direction (-1.6 % and +1.7 % then).

Contact boundary :math:`\Gamma_c`: the arc below y = -0.8 R (between
(±0.6 R, -0.8 R), where ``meshes/hertz.py`` puts geometry points, so that
:math:`|\Gamma_c| = 2R\arcsin 0.6` up to the polygon's chord error), ordered
along the arc from x < 0 to x > 0. The mesh must have radius R (checked).

Usage examples::

  python meshes/hertz.py            # meshes/hertz.mesh, if not present
  python sfepy_problems/hertz_cylinder.py \
      -d "mesh='meshes/hertz.mesh', output='output/hertz.npz'"
  python -m solver output/hertz.npz --method min --gap obstacle

The export prints one line, ``exported 7126 DOFs, 109 contact nodes ->
/.../output/hertz.npz``; ``-v`` shows SfePy's messages. ``sfepy-run
sfepy_problems/hertz_cylinder.py -d "..."`` does the same (with
``verbose=True`` in ``-d`` for SfePy's messages; see
``block_obstacle.py``).

The parameters of ``define()`` can all be set with ``-d``: ``mesh``,
``output`` (the ``.npz``; the unconstrained solution goes in the same folder
as ``.vtk``, named after the mesh), ``E``, ``nu``, ``plane`` ('strain' or
'stress'), ``d`` (the prescribed downward displacement of the top edge),
``R`` (the radius of the mesh), ``gamma_c_y`` (Γc is the arc below y =
gamma_c_y * R), ``obstacle_x``, ``obstacle_y``, ``order``, ``load``
('displacement' or 'force'), ``P`` (the force per unit length of
``load='force'``), ``verbose`` and ``solve`` (True: SfePy also solves the unconstrained problem and writes
its ``.vtk``, a check; False: export only, ``_export.NO_SOLVE``, see
``block_obstacle.py``);
with ``load='force'`` SfePy never solves.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates, relative to R.
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
    """``post_process_hook_final``: assemble K, f, M and write the ``.npz``."""
    conf = pb.conf.options
    R = conf.R
    coors = pb.domain.mesh.coors
    radius = nm.hypot(coors[:, 0], coors[:, 1]).max()
    if abs(radius - R) > 1e-6 * R:
        raise ValueError(f'the mesh has radius {radius:g}, but R = {R:g}: '
                         'pass R=... with -d, or another mesh')
    E_star = conf.E / (1.0 - conf.nu ** 2) if conf.plane == 'strain' \
        else conf.E
    force = conf.load == 'force'
    if force:
        load = {'force_y': -conf.P, 'on': 'top edge y = 0, uniform traction '
                f'{-conf.P / (2 * R):g}', 'u_x_pinned_at': [0.0, 0.0]}
    else:
        load = {'prescribed_displacement_y': -conf.d, 'on': 'top edge y = 0',
                'u_x_pinned_at': [0.0, 0.0]}
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load='dw_surface_ltr.i.Top(load.val, v)' if force else None,
        obstacle=conf.obstacle,
        meta={'E': conf.E, 'nu': conf.nu, 'plane': conf.plane,
              'R': R, 'E_star': E_star,
              # the force P given, or the displacement d (P is then known
              # only after the contact solve)
              **({'P': conf.P} if force else {'d': conf.d}),
              'load': load,
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/hertz_cylinder.py',
              'description': 'Hertz line contact: half-cylinder x^2 + y^2 '
                             '<= R^2, y <= 0 on the rigid line y = -R',
              'supports': 'u_x = 0 at (0, 0) (held by the contact in y '
                          'and in rotation)' if force else
                          'top edge y = 0: u_y = -d; u_x = 0 at (0, 0)',
              'contact_boundary': f'arc y < {conf.gamma_c_y:g} R',
              'hertz': 'a = 2 sqrt(P R / (pi E_star)), p0 = 2 P / (pi a), '
                       'P = sum of the vertical contact forces'},
    )


def define(mesh='meshes/hertz.mesh', output='output/hertz.npz',
           E=2e5, nu=0.3, plane='strain', d=0.016, R=1.0, gamma_c_y=-0.8,
           obstacle_x='t', obstacle_y=None, order=1, load='displacement',
           P=1739.6, solve=True, verbose=None):
    if load not in ('displacement', 'force'):
        raise ValueError(f"load must be 'displacement' or 'force', got "
                         f"{load!r}")
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    from solver.geometry.curves.parametric import ParametricCurve

    filename_mesh = op.abspath(mesh)  # SfePy resolves relative paths from
    # this file's folder; the user means the working directory.
    output_dir = op.dirname(op.abspath(output))
    if obstacle_y is None:
        obstacle_y = repr(-float(R))  # the line y = -R, e.g. '-1'
        if obstacle_y.endswith('.0'):
            obstacle_y = obstacle_y[:-2]

    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'post_process_hook_final': export_contact_problem,
        # without SfePy's solve (force load, or solve=False): no .vtk
        'save_results': load == 'displacement' and bool(solve),
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'plane': plane, 'd': d, 'R': R,
        'load': load, 'P': P,
        'gamma_c_y': gamma_c_y,
        'obstacle': ParametricCurve(obstacle_x, obstacle_y),
    }

    tol = TOL * R
    regions = {
        'Omega': 'all',
        'Top': (f'vertices in (y > {-tol})', 'facet'),
        'Centre': (f'vertices in (x > {-tol}) & (x < {tol}) & (y > {-tol})',
                   'vertex'),
        'Surface': ('vertices of surface', 'facet'),
        'Low': (f'vertices in (y < {gamma_c_y * R + tol})', 'facet'),
        # Boundary edges with both ends below y = gamma_c_y * R:
        'Gamma_c': ('r.Surface *e r.Low', 'facet'),  # *e: edges = facets in 2D
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(2, E, nu,
                                                    plane=plane)},),
        # the force P per unit length as a uniform traction on the top edge
        'load': ({'val': nm.array([[0.0], [-P / (2.0 * R)]])},),
    }

    fields = {
        'displacement': ('real', 'vector', 'Omega', order),
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
        'pressed': ('Top', {'u.1': -d}),
        'pinned': ('Centre', {'u.0': 0.0}),
    }
    if load == 'force':  # held in y and in rotation by the contact only
        del ebcs['pressed']

    integrals = {
        'i': 2 * order,
    }

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u) = 0"""
        if load == 'displacement' else
        """dw_lin_elastic.i.Omega(solid.D, v, u)
         = dw_surface_ltr.i.Top(load.val, v)""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        # K is singular under a force (no support in y): SfePy solves nothing
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6, 'eps_r': 1e-12}
                   if load == 'displacement' and solve
                   else dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
