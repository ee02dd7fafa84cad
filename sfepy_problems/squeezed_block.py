r"""
A block on rollers pressed by a rigid plane: the contact patch test of any
cell kind (triangles, quadrilaterals, tetrahedra, hexahedra; issue 35).

The block (the mesh's bounding box, of length L along x, d = 2 or 3;
below with its lowest corner at the origin) rests on rollers on its faces
x = 0, y = 0 (and z = 0): :math:`u_x = 0`, :math:`u_y = 0`
(:math:`u_z = 0`) there. A rigid plane enters its face x = L by δ: the
plane x = L − δ, the obstacle on its right. No load. The exact solution is
uniaxial compression, :math:`\varepsilon_{xx} = -\delta/L`, all other
stresses zero (plane strain: :math:`\sigma_{zz} = \nu\sigma_{xx}`): a
uniform contact pressure

.. math::
    p = E'\,\delta / L \;, \quad E' = E \;\text{(3D)}, \quad
    E' = E / (1 - \nu^2) \;\text{(plane strain)} \;,

and the displacement :math:`u_x = -\delta x / L`, :math:`u_y = \nu'
\delta y / L` (:math:`\nu' = \nu` in 3D, :math:`\nu / (1 - \nu)` in plane
strain), :math:`u_z = \nu \delta z / L`. The field is linear, so first-order
elements of every kind reproduce it to round-off; friction does not act
on it only for ν = 0 (otherwise the face x = L slides outward by the
Poisson effect). SfePy assembles K, f = 0 and M and solves nothing
(``NO_SOLVE``).

With ``sides=2`` the block is squeezed between **two** rigid planes (several
obstacles, issue 35): planes entering its faces x = x_min and x = x_max by
δ each, the block on rollers on its bottom y = y_min (u_y = 0; and on
z = z_min, u_z = 0) with u_x = 0 at the bottom's midpoint x = (x_min +
x_max)/2 (a node in 2D, the line along z in 3D; the mesh needs nodes
there). Γc is both faces. The closed form is the same compression with
twice the strain, :math:`\varepsilon_{xx} = -2\delta/L`, about the
mid-plane: p = 2E'δ/L, :math:`u_x = -2\delta (x - x_m)/L`, :math:`u_y =
2\nu'\delta (y - y_{min})/L`. In 2D the planes are two lines, one a
polyline and one a parametric curve (``obstacle_curves``); in 3D a
``several`` surface of two planes.

Usage::

  python sfepy_problems/squeezed_block.py \
      -d "mesh='meshes/box_hex_4.mesh', output='output/box_hex_4.npz'"
  python sfepy_problems/squeezed_block.py \
      -d "mesh='meshes/block_quad_200.mesh', output='output/squeezed_quad.npz'"
  python sfepy_problems/squeezed_block.py \
      -d "mesh='meshes/block_quad_200.mesh', output='output/squeezed2_quad.npz', sides=2"

Any box-shaped mesh will do, e.g. SfePy's own ``meshes/3d/cube_medium_hexa.mesh``
(in the ``sfepy`` package's data folder).

``-d`` also takes ``E``, ``nu``, ``delta``, ``sides`` (1 or 2) and
``verbose``.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates, relative to L.
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


def obstacle(dim, low, high, delta, sides=1):
    """The plane x = x_max − δ (``low``, ``high``: the box's corners): a
    vertical line (polyline) in 2D, a plane spec in 3D, its normal towards
    the body (−x); ``sides=2`` also the plane x = x_min + δ (2D: a
    parametric line x = x_min + δ, y = t on the box's y-range and beyond),
    the two as several obstacles."""
    x = float(high[0] - delta)
    if dim == 2:
        span = float(high[1] - low[1])
        right = {'points': [[x, low[1] - span], [x, high[1] + span]]}
        if sides == 1:
            return right
        left = {'x': repr(float(low[0] + delta)), 'y': 't',
                't_range': [low[1] - span, high[1] + span]}
        return {'curves': [left, right]}
    right = {'kind': 'plane', 'point': [x, 0.0, 0.0],
             'normal': [-1.0, 0.0, 0.0]}
    if sides == 1:
        return right
    left = {'kind': 'plane', 'point': [float(low[0] + delta), 0.0, 0.0],
            'normal': [1.0, 0.0, 0.0]}
    return {'kind': 'several', 'surfaces': [left, right]}


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: assemble K, f = 0, M, write the ``.npz``."""
    conf = pb.conf.options
    dim = pb.domain.mesh.dim
    meta = {'E': conf.E, 'nu': conf.nu, 'load': {'plane_enters': conf.delta},
            'mesh': op.basename(pb.conf.filename_mesh),
            'problem_file': 'sfepy_problems/squeezed_block.py',
            'supports': 'rollers on x = 0, y = 0' + (', z = 0' if dim == 3
                                                     else ''),
            'contact_boundary': f'face x = {conf.high[0]:g}'}
    if conf.sides == 2:
        meta.update(load={'planes_enter': conf.delta},
                    supports='rollers on y = 0' + (', z = 0' if dim == 3
                                                   else '')
                    + ', u_x = 0 at the bottom midpoint',
                    contact_boundary=f'faces x = {conf.low[0]:g} and '
                                     f'x = {conf.high[0]:g}')
    if dim == 2:
        meta['plane'] = 'strain'
    return _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=obstacle(dim, conf.low, conf.high, conf.delta, conf.sides),
        meta=meta)


def define(mesh='meshes/box_hex_4.mesh', output='output/box_hex_4.npz',
           E=100.0, nu=0.3, delta=1e-3, sides=1, verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    from sfepy.discrete.fem import Mesh

    filename_mesh = op.abspath(mesh)
    coors = Mesh.from_file(filename_mesh).coors
    dim = coors.shape[1]
    low, high = coors.min(axis=0).tolist(), coors.max(axis=0).tolist()
    tol = TOL * max(h - lo for lo, h in zip(low, high))
    options = {
        'output_dir': op.dirname(op.abspath(output)),
        'output_format': 'vtk',
        'save_results': False,  # SfePy solves nothing (NO_SOLVE)
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'delta': delta, 'low': low, 'high': high,
        'sides': int(sides),
    }
    if sides not in (1, 2):
        raise ValueError(f'sides must be 1 or 2, got {sides!r}')
    axes = 'xyz'[:dim]
    regions = {'Omega': 'all',
               'Gamma_c': (f'vertices in (x > {high[0] - tol})', 'facet')}
    ebcs = {}
    for k, axis in enumerate(axes):
        if sides == 2 and k == 0:  # u_x = 0 at the bottom's midpoint only
            mid = 0.5 * (low[0] + high[0])
            regions['Middle'] = (
                f'vertices in (x > {mid - tol}) & (x < {mid + tol}) '
                f'& (y < {low[1] + tol})', 'vertex')
            ebcs['middle_x'] = ('Middle', {'u.0': 0.0})
            continue
        regions[f'Roller_{axis}'] = (
            f'vertices in ({axis} < {low[k] + tol})', 'facet')
        ebcs[f'roller_{axis}'] = (f'Roller_{axis}', {f'u.{k}': 0.0})
    if sides == 2:
        regions['Gamma_c'] = (f'vertices in (x < {low[0] + tol}) '
                              f'+v vertices in (x > {high[0] - tol})',
                              'facet')

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(dim, E, nu,
                                                    plane='strain')},),
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
    integrals = {'i': 2}
    equations = {
        'balance_of_forces': 'dw_lin_elastic.i.Omega(solid.D, v, u) = 0',
    }
    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }
    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
