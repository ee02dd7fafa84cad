r"""
A block resting on a rigid floor under its own weight: a body held only by
the contact (no Dirichlet condition at all).

The thesis's block (10 × 20, E = 2·10⁵, ν = 0.3, plane strain, the mesh
``meshes/block_454.mesh`` on [-5, 5] × [-10, 10]) stands on the rigid line
y = -10 (Γo(t) = [t, -10]), touching it along its whole bottom edge Γc,
and is loaded by its weight, the body force b = (0, -ρg):

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    = \int_{\Omega} \ul{b} \cdot \ul{v} \;, \quad \forall \ul{v} \;.

K is singular: its kernel is the block's three rigid-body motions. The
solver finds them from the geometry and solves the contact problem with
the equilibrium Rᵀ(f − Bᵀλ) = 0 (``solver/contact/strategies/
floating.py``): the total contact force equals the weight, to round-off.
The floor's normals are vertical, so no contact resists a horizontal
translation; under a load without a horizontal component the block's
horizontal position is set to no motion. A horizontal load (``b`` with
an x component) is refused: frictionless contact cannot hold it.

Usage::

  sfepy-run sfepy_problems/block_on_floor.py \
      -d "mesh='meshes/block_454.mesh', output='output/block_floor.npz'"
  python -m solver output/block_floor.npz

Parameters (``-d``): ``mesh``, ``output``, ``E``, ``nu``, ``plane``,
``rho_g`` (the weight per unit volume, default 7.85e-5 N/mm³: steel),
``b`` (the body force vector, default (0, -rho_g)), ``floor`` (the
floor's height, default the mesh's lowest y), ``verbose``.
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


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: assemble K, f, M and write the ``.npz``."""
    conf = pb.conf.options
    coors = pb.domain.mesh.coors
    area = float(pb.evaluate('ev_volume.i.Omega(u)', verbose=False))
    _load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        load='dw_volume_lvf.i.Omega(load.val, v)',
        obstacle=conf.obstacle,
        meta={'E': conf.E, 'nu': conf.nu, 'plane': conf.plane,
              'load': {'body_force': list(map(float, conf.b)),
                       'area': area,
                       'weight': [float(c) * area for c in conf.b]},
              'mesh': op.basename(pb.conf.filename_mesh),
              'problem_file': 'sfepy_problems/block_on_floor.py',
              'supports': 'none: held by the contact only',
              'contact_boundary': f'bottom edge y = {coors[:, 1].min():g}'},
    )


def define(mesh='meshes/block_454.mesh', output='output/block_floor.npz',
           E=2e5, nu=0.3, plane='strain', rho_g=7.85e-5, b=None, floor=None,
           verbose=None):
    export = _load_export()
    export.set_verbosity(verbose)  # before SfePy's 'left over:'
    from sfepy.discrete.fem import Mesh
    from solver.geometry.curves.parametric import ParametricCurve

    filename_mesh = op.abspath(mesh)
    output_dir = op.dirname(op.abspath(output))
    bottom = float(Mesh.from_file(filename_mesh).coors[:, 1].min())
    floor = bottom if floor is None else float(floor)
    b = (0.0, -rho_g) if b is None else tuple(map(float, b))

    options = {
        'output_dir': output_dir,
        'output_format': 'vtk',
        'save_results': False,  # K is singular: SfePy solves nothing
        'post_process_hook_final': export_contact_problem,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'plane': plane, 'b': b,
        'obstacle': ParametricCurve('t', repr(floor)),
    }

    regions = {
        'Omega': 'all',
        'Gamma_c': (f'vertices in (y < {bottom + TOL})', 'facet'),
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(2, E, nu,
                                                    plane=plane)},),
        'load': ({'val': nm.array(b, dtype=nm.float64).reshape(2, 1)},),
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

    ebcs = {}

    integrals = {
        'i': 2,
    }

    equations = {
        'balance_of_forces':
        """dw_lin_elastic.i.Omega(solid.D, v, u)
         = dw_volume_lvf.i.Omega(load.val, v)""",
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(_load_export().main(__file__))
