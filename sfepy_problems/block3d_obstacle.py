r"""
The thesis block in 3D: extruded in z, pressed against a parabolic cylinder.

The 3D counterpart of ``block_obstacle.py`` (issue 18). The body is the
block :math:`\Omega = [-5, 5] \times [-10, 10] \times [0, T]`
(``meshes/block3d.py``: a thesis mesh extruded in ``layers`` layers), E =
2e5, ν = 0.3, the bottom y = −10 clamped, the contact surface
:math:`\Gamma_c` the face x = 5, the load F = (4000, 0, 0) *per unit
thickness* along the top-left edge x = −5, y = 10 (nodal forces F times each
node's share of the edge length: F·h/2 at the two ends, F·h inside, for
layers of thickness h; the total is F·T, as the 2D point force is per unit
thickness in plane strain). The rigid obstacle is the thesis's
parabola x = 5.05 + 0.005 y² swept along z, a parabolic cylinder, as a
parametric surface spec

.. code-block:: json

    {"kind": "parametric", "x": "5.05 + 0.005*t**2", "y": "t", "z": "s",
     "s_range": [-1, T + 1], "t_range": [-20, 20]}

whose normal c_s × c_t = (−1, 0.01 t, 0)/|·| points towards the body.
The exported K, f, M are (``_export.py``)

.. math::
    \ul{v}^T K \ul{u} = \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    \;, \quad
    \ul{v}^T f = \sum_{A} \ul{F}_A \cdot \ul{v}(\ul{x}_A) \;, \quad
    M_{ij} = \int_{\Gamma_c} \varphi_i \varphi_j \;.

SfePy solves nothing (``_export.NO_SOLVE``).

**Plane-strain slab** (``slab=True``, "2D as a special case"): on a one-layer
mesh of thickness T, u_z = 0 at every node (so also ε_zz = 0); with the
load per unit thickness the slab's contact forces per unit thickness are
comparable with the 2D block's. They are not identical: a field that does
not depend on z is interpolated by the tetrahedra of a prism exactly as by
its triangle (so the 2D displacements are admissible and give the 2D
energy times T), but the front and back nodes may also move differently,
which makes the slab slightly softer than the 2D model: without contact,
the 118-triangle slab's displacements differ from the 2D block's by 0.25 %
(front face z = 0) and 0.9 % (back face) of the largest. Tying them
(u(x, y, T) = u(x, y, 0)) is not expressible in the format's one-to-one
``dof_map``.

Usage (from the repository root)::

  sfepy-run sfepy_problems/block3d_obstacle.py \
      -d "mesh='meshes/block3d_454x5.mesh', output='output/block3d_454x5.npz'"
  sfepy-run sfepy_problems/block3d_obstacle.py \
      -d "mesh='meshes/block3d_118_slab.mesh', output='output/block3d_118_slab.npz', slab=True"

They print ``exported 4428 DOFs, 120 contact nodes -> PATH`` and
``exported 276 DOFs, 22 contact nodes -> PATH`` (``python
sfepy_problems/block3d_obstacle.py -d "..."`` does the same). Parameters
(``-d``): ``mesh``, ``output``, ``E``, ``nu``, ``F`` (per unit thickness),
``obstacle_x`` ('5.05 + 0.005*t**2'), ``obstacle_y`` ('t'), ``slab``,
``verbose``.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

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


def load_layers(filename_mesh):
    """Heights of the nodes on the loaded edge x = -5, y = 10, checked to
    be equally spaced (the trapezoidal shares are then h/2 at the two ends,
    h inside)."""
    from sfepy.discrete.fem import Mesh

    coors = Mesh.from_file(filename_mesh).coors
    on = (coors[:, 0] < -5 + TOL) & (coors[:, 1] > 10 - TOL)
    z = nm.sort(coors[on, 2])
    h = nm.diff(z)
    if len(z) < 2 or nm.ptp(h) > 1e-9 * h.max():
        raise ValueError('the edge x = -5, y = 10 needs equally spaced '
                         'nodes (a mesh of meshes/block3d.py)')
    return z


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: assemble K, f, M and write the ``.npz``."""
    conf = pb.conf.options
    z = pb.domain.mesh.coors[:, 2]
    T = float(z.max() - z.min())
    return _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load=conf.load,
        obstacle={'kind': 'parametric', 'x': conf.obstacle_x,
                  'y': conf.obstacle_y, 'z': 's',
                  's_range': [float(z.min()) - 1.0, float(z.max()) + 1.0],
                  't_range': [-20.0, 20.0]},
        meta={'E': conf.E, 'nu': conf.nu, 'thickness': T,
              'slab': bool(conf.slab),
              'load': {'line_force_per_thickness': list(map(float, conf.F)),
                       'along': 'edge x = -5, y = 10',
                       'total': [float(c) * T for c in conf.F]},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/block3d_obstacle.py',
              'supports': 'bottom y = -10 clamped'
                          + ('; u_z = 0 everywhere (plane strain slab)'
                             if conf.slab else ''),
              'contact_boundary': 'face x = 5'},
    )


def define(mesh='meshes/block3d_454x5.mesh',
           output='output/block3d_454x5.npz', E=2e5, nu=0.3,
           F=(4000.0, 0.0, 0.0), obstacle_x='5.05 + 0.005*t**2',
           obstacle_y='t', slab=False, verbose=None):
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
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'F': F, 'slab': slab,
        'obstacle_x': obstacle_x, 'obstacle_y': obstacle_y,
    }

    z = load_layers(filename_mesh)
    h, tol = z[1] - z[0], TOL * max(1.0, z[-1])
    edge = f'(x < {-5 + TOL}) & (y > {10 - TOL})'
    regions = {
        'Omega': 'all',
        'Gamma_D': (f'vertices in (y < {-10 + TOL})', 'facet'),
        'Gamma_c': (f'vertices in (x > {5 - TOL})', 'facet'),
        # The loaded edge: its end nodes carry h/2 of it, the others h.
        'LoadEnds': (f'vertices in {edge} & ((z < {z[0] + tol}) | '
                     f'(z > {z[-1] - tol}))', 'vertex'),
    }
    load = 'dw_point_load.0.LoadEnds(end.val, v)'
    if len(z) > 2:  # a one-layer slab has no inner node
        regions['LoadInner'] = (f'vertices in {edge} & (z > {z[0] + tol}) '
                                f'& (z < {z[-1] - tol})', 'vertex')
        load += ' + dw_point_load.0.LoadInner(inner.val, v)'
    options['load'] = load  # read by the hook
    force = nm.asarray(F, dtype=nm.float64)
    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(3, E, nu)},),
        'end': ({'.val': force * h / 2},),
        'inner': ({'.val': force * h},),
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
        'clamped': ('Gamma_D', {'u.all': 0.0}),
    }
    if slab:
        ebcs['plane_strain'] = ('Omega', {'u.2': 0.0})

    integrals = {
        'i': 2,
    }

    equations = {
        'balance_of_forces':
        f'dw_lin_elastic.i.Omega(solid.D, v, u) = {load}',
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
