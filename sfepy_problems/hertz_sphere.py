r"""
Hertz point contact: an elastic quarter sphere pressed onto a rigid plane.

The 3D counterpart of ``hertz_cylinder.py`` (issue 18): SfePy assembles K,
f and M of the body, the contact solver (``python -m solver``) solves the
contact. SfePy solves nothing here: its direct solve of the elasticity
problem takes minutes at 10⁴–10⁵ DOFs in 3D, so the export runs on the
initial state (``_export.NO_SOLVE``, ``_export.export_only``).

The body :math:`\Omega` is the quarter of the lower half-ball of radius R
centred at (0, 0, R): :math:`x^2 + y^2 + (z - R)^2 \le R^2`, x ≥ 0, y ≥ 0,
z ≤ R (``meshes/hertz_sphere.py``). It touches the rigid plane z = 0 (the
obstacle, ``{"kind": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]}``)
at the origin.

Find :math:`\ul{u}` such that

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

with :math:`u_z = -\delta` on the flat top z = R, :math:`u_x = 0` on the
symmetry plane x = 0 and :math:`u_y = 0` on y = 0; D is the isotropic
elasticity tensor of E, ν. The exported K is reduced to the free DOFs, f is
the lifting :math:`-(K_{full} u_D)_F` of the prescribed top displacement,
M is :math:`\int_{\Gamma_c} \varphi_i \varphi_j` on the contact surface.

**A prescribed displacement (default) or a force** (as in
``hertz_cylinder.py``): with ``load='force'`` the top carries the whole
sphere's force P (P/4 on the quarter) as a uniform traction and is free in
z, the vertical translation held by the contact only (K singular, solved
exactly: issue 31). By default: The top may slide in x and y; with the two symmetry planes this
removes every rigid motion, so K is symmetric positive definite. The total
force of the *whole* sphere is :math:`P = 4 \sum_i \lambda_{i,z}` (four
quarters), known after the contact solve (the sum of the vertical contact
forces, equal to the top reaction). Hertz (rigid plane,
:math:`E^* = E/(1-\nu^2)`):

.. math::
    a = \left(\frac{3 P R}{4 E^*}\right)^{1/3}, \quad
    p_0 = \frac{3P}{2\pi a^2}, \quad p(r) = p_0 \sqrt{1 - r^2/a^2}\;.

Defaults: R = 1, E = 2e5, ν = 0.3, δ = 0.00243 (the top's approach; it
gives a ≈ 0.05 R, the contact radius ``meshes/hertz_sphere.py`` refines
for; less than Hertz's approach a²/R = 0.0025 of a half-space, whose far
field reaches further than the top of the half ball: measured with a
condensed contact solve, a = 0.04996 from Hertz's formula with the computed
P at a/h = 32). a/R = 0.05 rather than 0.1 keeps Hertz's own error on a
true sphere (a paraboloid in his theory) below the study's targets:
``solver.verification.sphere_flat_contact``. ``meta`` carries R, E, nu,
E_star, delta, a_target (0.05 R), contact_center (the first touching
point, on the axis), h_contact (the mean edge of the contact
triangles within a_target of the origin) and a_h = a_target / h_contact.

Contact surface :math:`\Gamma_c`: the spherical facets with all vertices
below z = ``gamma_c_z`` · R (default 0.2: a cap of radius 0.6 R), minus the
facets on the symmetry planes (``-s``; mind SfePy's right-to-left grouping
of region operators, ``define()``); exported as outward triangles
(``contact_faces``; their normals point to −z near the contact).

Usage (from the repository root)::

  python meshes/hertz_sphere.py --a-over-h 4 -o meshes/hertz_sphere_4.mesh
  sfepy-run sfepy_problems/hertz_sphere.py \
      -d "mesh='meshes/hertz_sphere_4.mesh', output='output/hertz_sphere_4.npz'"
  python sfepy_problems/hertz_sphere.py \
      -d "mesh='meshes/hertz_sphere_4.mesh', output='output/hertz_sphere_4.npz'"

Both print ``exported 2443 DOFs, 172 contact nodes -> PATH``. Parameters
(``-d``): ``mesh``, ``output``, ``E``, ``nu``, ``R`` (must be the mesh's
radius), ``delta``, ``gamma_c_z``, ``a_target``, ``verbose``.
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


def contact_size(coors, faces, radius):
    """Mean edge length of the faces (triangles or quadrilaterals) with a
    vertex within ``radius`` of the z axis (the element size h at the
    contact)."""
    near = (nm.hypot(coors[faces, 0], coors[faces, 1]) < radius).any(axis=1)
    tri = coors[faces[near]]
    edges = tri - nm.roll(tri, -1, axis=1)
    return float(nm.sqrt((edges ** 2).sum(axis=2)).mean())


def top_area(filename_mesh, R):
    """The area of the mesh's flat top z = R (its boundary faces: triangles
    of tetrahedra or quadrilaterals of hexahedra, area ½|d₁ × d₂| by the
    diagonals)."""
    from sfepy.discrete.fem import Mesh

    mesh = Mesh.from_file(filename_mesh)
    coors = mesh.coors
    if '3_8' in mesh.descs:
        cells = mesh.get_conn('3_8')
        corners = [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5],
                   [2, 3, 7, 6], [3, 0, 4, 7]]
    else:
        cells = mesh.get_conn('3_4')
        corners = [[0, 1, 2, 2], [0, 1, 3, 3], [0, 2, 3, 3], [1, 2, 3, 3]]
    top = nm.abs(coors[:, 2] - R) < TOL * R
    faces = cells[:, corners].reshape(-1, 4)
    p = coors[faces[top[faces].all(axis=1)]]
    return 0.5 * float(nm.linalg.norm(nm.cross(p[:, 2] - p[:, 0],
                                               p[:, 3] - p[:, 1]),
                                      axis=1).sum())


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: assemble K, f, M, write the ``.npz``."""
    conf = pb.conf.options
    R = conf.R
    coors = pb.domain.mesh.coors
    radius = nm.sqrt(((coors - [0, 0, R]) ** 2).sum(axis=1)).max()
    if abs(radius - R) > 1e-6 * R:
        raise ValueError(f'the mesh has radius {radius:g}, but R = {R:g}: '
                         'pass R=... with -d, or another mesh')
    export = _load_export()
    cells = export.mesh_cells(pb.domain.mesh)
    h = contact_size(coors, export.contact_triangles(pb, 'Gamma_c', cells,
                                                     coors), conf.a_target)
    force = conf.load == 'force'
    return export.export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load='dw_surface_ltr.i.Top(load.val, v)' if force else None,
        obstacle={'kind': 'plane', 'point': [0.0, 0.0, 0.0],
                  'normal': [0.0, 0.0, 1.0]},
        meta={'E': conf.E, 'nu': conf.nu, 'R': R,
              **({'P': conf.P} if force else {'delta': conf.delta}),
              'E_star': conf.E / (1.0 - conf.nu ** 2),
              'a_target': conf.a_target, 'h_contact': h,
              'a_h': conf.a_target / h, 'quarter': True,
              'contact_center': [0.0, 0.0, 0.0],
              'load': ({'force_z': -conf.P, 'quarter_force_z': -conf.P / 4,
                        'on': 'top z = R, uniform traction'}
                       if force else
                       {'prescribed_displacement_z': -conf.delta,
                        'on': 'top z = R'}),
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/hertz_sphere.py',
              'description': 'Hertz point contact: quarter sphere '
                             '|x - (0,0,R)| <= R, x, y >= 0, z <= R on the '
                             'rigid plane z = 0',
              'supports': ('u_x = 0 on x = 0; u_y = 0 on y = 0 (held by '
                           'the contact in z)') if force else
                          'top z = R: u_z = -delta; u_x = 0 on x = 0; '
                          'u_y = 0 on y = 0',
              'contact_boundary': f'sphere below z = {conf.gamma_c_z:g} R',
              'hertz': 'P = 4 * sum of the vertical contact forces (the '
                       'whole sphere); a = (3 P R / (4 E_star))^(1/3), '
                       'p0 = 3 P / (2 pi a^2)'},
    )


def define(mesh='meshes/hertz_sphere_4.mesh',
           output='output/hertz_sphere.npz', E=2e5, nu=0.3, R=1.0,
           delta=0.00243, gamma_c_z=0.2, a_target=None, load='displacement',
           P=36.63, verbose=None):
    if load not in ('displacement', 'force'):
        raise ValueError(f"load must be 'displacement' or 'force', got "
                         f"{load!r}")
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'

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
        'E': E, 'nu': nu, 'R': R, 'delta': delta, 'gamma_c_z': gamma_c_z,
        'load': load, 'P': P,
        'a_target': 0.05 * R if a_target is None else a_target,
    }

    tol = TOL * R
    regions = {
        'Omega': 'all',
        'Top': (f'vertices in (z > {R - tol})', 'facet'),
        'X0': (f'vertices in (x < {tol})', 'facet'),
        'Y0': (f'vertices in (y < {tol})', 'facet'),
        'Surface': ('vertices of surface', 'facet'),
        'Low': (f'vertices in (z < {gamma_c_z * R + tol})', 'facet'),
        # Spherical facets below z = gamma_c_z R (*s, -s, +s: facet set
        # ops). SfePy groups region operators from the right: without the
        # parentheses 'A -s B -s C' would be A - (B - C).
        'Gamma_c': ('(r.Surface *s r.Low) -s (r.X0 +s r.Y0)', 'facet'),
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(3, E, nu)},),
        # the whole sphere's force P: P/4 as a uniform traction on the
        # quarter model's (polygonal) top face
        'load': ({'val': nm.array([[0.0], [0.0],
                                   [-P / 4 / top_area(filename_mesh, R)]])},),
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
        'pressed': ('Top', {'u.2': -delta}),
        'symmetry_x': ('X0', {'u.0': 0.0}),
        'symmetry_y': ('Y0', {'u.1': 0.0}),
    }
    if load == 'force':  # the vertical translation is held by contact only
        del ebcs['pressed']

    integrals = {
        'i': 2,
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
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
