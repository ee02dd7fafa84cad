r"""
The thesis's §4 model: an elastic block pressed against a rigid parabola.

This problem file assembles and **exports** the discrete model of the
contact problem in the thesis's workflow: SfePy builds the stiffness matrix
K, the load vector f and the boundary matrix M; the contact solver
(``python -m solver``, which never imports SfePy) reads them from an
``.npz`` file. SfePy itself only solves the unconstrained linear elasticity
problem below (no contact), whose solution is written as usual and is used
to check the exported K.

Find :math:`\ul{u}` such that:

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    = \ul{F} \cdot \ul{v}(\ul{x}_A)
    \;, \quad \forall \ul{v} \;,

with :math:`\ul{u} = \ul{0}` on :math:`\Gamma_D`, where :math:`D_{ijkl}` is
the plane strain (or plane stress) isotropic elasticity tensor for E, ν. The
exported matrices are (thesis (56)-(69), (80))

.. math::
    \ul{v}^T K \ul{u} = \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    \;, \quad
    \ul{v}^T f = \ul{F} \cdot \ul{v}(\ul{x}_A)
    \;, \quad
    M_{ij} = \int_{\Gamma_c} \varphi_i \varphi_j \;,

K and f reduced to the free DOFs (Dirichlet DOFs eliminated), M over the
nodes of :math:`\Gamma_c` ordered along it.

Geometry and loads (thesis §4): the block :math:`\Omega = [-5, 5] \times
[-10, 10]`, E = 2e5, ν = 0.3, plane strain, a point force F = (4000, 0), and
the obstacle :math:`\Gamma_o(t) = [5.05 + 0.005 t^2, t]` right of the edge
x = 5 (gap 0.05 at y = 0).

**Reconstruction of the lost Fig. 3.** The text copy of the thesis lost the
figure that shows the supports and where F acts. We take: the bottom edge
y = -10 clamped (:math:`\Gamma_D`), F applied at the top-left corner
:math:`\ul{x}_A = (-5, 10)`, and the contact boundary :math:`\Gamma_c` = the
right edge x = 5. Reason: the block then bends to the right like a
cantilever, so the unconstrained solution crosses the obstacle only for
y ≳ -3.7 and the contact zone is partial, as in the thesis's Fig. 4; a force
at mid-height or a roller support would give a full or a rigid-body contact.
The clamped corner (5, -10) lies on both :math:`\Gamma_D` and
:math:`\Gamma_c`: it is kept in M (so that :math:`\sum M = |\Gamma_c| = 20`)
and marked as a support (no free DOFs) in the exported ``contact_dofs``.

Usage examples::

  python sfepy_problems/block_obstacle.py \
      -d "mesh='meshes/block_118.mesh', output='output/block_118.npz'"
  python sfepy_problems/block_obstacle.py \
      -d "mesh='meshes/block_454.mesh', output='output/block_454.npz'"
  python sfepy_problems/block_obstacle.py \
      -d "mesh='meshes/block_1878.mesh', output='output/block_1878.npz'"
  python -m solver output/block_454.npz

Each export prints one line, e.g. ``exported 492 DOFs, 20 contact nodes ->
/.../output/block_454.npz``. ``python FILE.py`` takes ``sfepy-run``'s
options and runs it quietly; ``-v`` shows SfePy's messages. ``sfepy-run
sfepy_problems/block_obstacle.py -d "..."`` does the same export, quiet too
except for the notice SfePy prints at its start when jax is not installed;
add ``verbose=True`` to ``-d`` (or set ``CONTACT_SSN_VERBOSE=1``) for SfePy's
messages there (``_export.py``).

The parameters of ``define()`` can all be set with ``-d``: ``mesh``,
``output`` (the ``.npz``; the unconstrained solution goes in the same folder
as ``.vtk``, named after the mesh), ``E``, ``nu``, ``plane`` ('strain' or
'stress'), ``F`` (the force vector), the obstacle (``obstacle_x``,
``obstacle_y``, or ``obstacle_points``, a list of (x, y) vertices of a
polyline obstacle, e.g. ``-d "obstacle_points=[(5.5, -10), (5.1, 0), (5.5,
10)]"``), ``solve`` and ``verbose``.

``solve=False`` exports without SfePy's own solve of the unconstrained
problem (``_export.NO_SOLVE``, as the 3D files do; no ``.vtk`` is
written): K, f and M do not depend on it, and at 10⁶–10⁷ DOFs that direct
solve is most of the export's time and memory (benchmarks/README.md, "2D
at 10⁷ DOFs"). The default keeps it, as a check of the exported K at the
thesis's sizes.
"""
import importlib.util
import os.path as op
import sys

import numpy as nm

from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

#: Tolerance of region selection by coordinates (gmsh noise is ~1e-12).
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
    """``post_process_hook_final``: assemble K, f, M and write the ``.npz``.

    K and f are evaluated in weak mode with the Dirichlet conditions applied,
    which gives them reduced to the free DOFs (the thesis's Ñ unknowns); the
    clamp is homogeneous, so f is the point force alone. M is evaluated with
    a scalar P1 field on Omega, restricted to the nodes of Gamma_c in the
    order along the edge. The work is done by the shared
    :func:`_export.export_contact_problem`.
    """
    conf = pb.conf.options
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load='dw_point_load.0.Load(load.val, v)',
        obstacle=conf.obstacle,
        meta={'E': conf.E, 'nu': conf.nu, 'plane': conf.plane,
              'load': {'point_force': list(map(float, conf.F)),
                       'at': list(map(float, conf.load_point))},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/block_obstacle.py',
              'supports': 'bottom edge y = -10 clamped',
              'contact_boundary': 'right edge x = 5'},
    )


def define(mesh='meshes/block_454.mesh', output='output/block_454.npz',
           E=2e5, nu=0.3, plane='strain', F=(4000.0, 0.0),
           obstacle_x='5.05 + 0.005*t**2', obstacle_y='t', order=1,
           obstacle_points=None, solve=True, verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    from solver.geometry.curves.parametric import ParametricCurve
    from solver.geometry.curves.polyline import PolylineCurve

    filename_mesh = op.abspath(mesh)  # SfePy resolves relative paths from
    # this file's folder; the user means the working directory.
    output_dir = op.dirname(op.abspath(output))
    load_point = (-5.0, 10.0)

    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': bool(solve),  # no solve: no .vtk of a zero field
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'plane': plane, 'F': F, 'load_point': load_point,
        'obstacle': (ParametricCurve(obstacle_x, obstacle_y)
                     if obstacle_points is None
                     else PolylineCurve(obstacle_points)),
    }

    regions = {
        'Omega': 'all',
        'Gamma_D': (f'vertices in (y < {-10 + TOL})', 'facet'),
        'Gamma_c': (f'vertices in (x > {5 - TOL})', 'facet'),
        'Load': (f'vertices in (x < {-5 + TOL}) & (y > {10 - TOL})',
                 'vertex'),
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(2, E, nu,
                                                    plane=plane)},),
        'load': ({'.val': nm.asarray(F, dtype=nm.float64)},),
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
        'clamped': ('Gamma_D', {'u.all': 0.0}),
    }

    integrals = {
        'i': 2 * order,
    }

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u)
         = dw_point_load.0.Load(load.val, v)""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', {'i_max': 1, 'eps_a': 1e-6,
                                  'eps_r': 1e-12} if solve
                   else dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
