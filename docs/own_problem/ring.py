r"""
A ring expanded into a rigid housing: the example of ``docs/own-problem.md``.

A thick elastic ring, inner radius a, outer radius b, sits in a rigid
housing whose bore has the radius b + g (a clearance g). A mandrel pushes
the ring's inner surface outwards by δ: the ring expands, closes the
clearance and is pressed against the bore. By symmetry a quarter of the
ring is modelled, :math:`\Omega = \{a \le r \le b,\ x \ge 0,\ y \ge 0\}`
(``ring_mesh.py``).

Find :math:`\ul{u}` such that

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

with D the plane strain elasticity tensor of E, ν and the Dirichlet
conditions

* :math:`\ul{u} = \delta\, \ul{x} / a` on the inner arc r = a (pushed out
  radially by δ; both components prescribed, so no rigid motion is left),
* :math:`u_x = 0` on x = 0 and :math:`u_y = 0` on y = 0 (symmetry),

and contact of the outer arc :math:`\Gamma_c` (r = b) with the rigid circle
:math:`\Gamma_o(t) = (b + g)(\cos t, \sin t)`. The contact solver
(``python -m solver``) solves the contact; this file only exports K, f, M
(``sfepy_problems.export``). The end nodes of :math:`\Gamma_c` lie on the
symmetry lines and take part in the contact as rollers.

**Closed form** (Lamé; plane strain). In a ring loaded uniformly around,
:math:`u_r = A r + B / r` and
:math:`\sigma_{rr} = 2(\lambda + \mu) A - 2 \mu B / r^2`. Once the ring
touches the bore everywhere, :math:`u_r(a) = \delta` and
:math:`u_r(b) = g` give A and B, and the contact pressure is
:math:`p = -\sigma_{rr}(b)` (``check_ring.py`` computes it from ``meta``).
The ring touches the bore when its free expansion,
:math:`u_r(b) = 2 \delta a b (1 - \nu) / (a^2 + (1 - 2\nu) b^2)`
(:math:`\sigma_{rr}(b) = 0`), exceeds g.

Usage examples::

  python ring_mesh.py
  python ring.py -d "mesh='ring.mesh', output='ring.npz'"
  sfepy-run ring.py -d "mesh='ring.mesh', output='ring.npz'"
  python -m solver ring.npz -o ring-solved

Parameters (``-d``): ``mesh``, ``output``, ``E`` (2e5), ``nu`` (0.3),
``a`` (1) and ``b`` (2), the mesh's radii, ``gap`` (1e-3), ``delta``
(4e-3), ``verbose``.
"""
import os.path as op
import sys

import numpy as np
from sfepy.mechanics.matcoefs import stiffness_from_youngpoisson

from sfepy_problems import export

#: Tolerance of region selection by coordinates, relative to b.
TOL = 1e-8


def export_hook(pb, variables):
    """``post_process_hook_final``: assemble K, f, M and write the ``.npz``."""
    conf = pb.conf.options
    radius = np.hypot(*pb.domain.mesh.coors.T)
    if abs(radius.min() - conf.a) > TOL * conf.b \
            or abs(radius.max() - conf.b) > TOL * conf.b:
        raise ValueError(f'the mesh has radii {radius.min():g} and '
                         f'{radius.max():g}, not a = {conf.a:g}, '
                         f'b = {conf.b:g}: pass a=..., b=... with -d')
    bore = repr(conf.b + conf.gap)
    export.export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)',
        obstacle={'x': f'{bore}*cos(t)', 'y': f'{bore}*sin(t)'},
        meta={'E': conf.E, 'nu': conf.nu, 'plane': 'strain',
              'load': {'prescribed_radial_displacement': conf.delta,
                       'on': 'inner arc r = a'},
              'mesh': op.basename(pb.conf.filename_mesh),
              'description': 'quarter ring a <= r <= b expanded into a '
                             'rigid bore of radius b + gap',
              'a': conf.a, 'b': conf.b, 'gap': conf.gap,
              'delta': conf.delta})


def define(mesh='ring.mesh', output='ring.npz', E=2e5, nu=0.3, a=1.0,
           b=2.0, gap=1e-3, delta=4e-3, verbose=None):
    export.set_verbosity(verbose)  # before SfePy's 'left over:' message

    filename_mesh = op.abspath(mesh)
    options = {
        'output_dir': op.dirname(op.abspath(output)),
        'save_results': False,  # SfePy solves nothing (export.NO_SOLVE)
        'post_process_hook_final': export_hook,
        'nls': 'newton',
        'ls': 'ls',
        # Read by the hook:
        'export': op.abspath(output),
        'E': E, 'nu': nu, 'a': a, 'b': b, 'gap': gap, 'delta': delta,
    }

    tol = TOL * b

    def inner_arc(coors, domain=None):
        """The vertices on r = a (region expressions compare single
        coordinates only, so a circle needs a function)."""
        return np.flatnonzero(np.hypot(*coors.T) < a + tol)

    def outer_arc(coors, domain=None):
        """The vertices on r = b."""
        return np.flatnonzero(np.hypot(*coors.T) > b - tol)

    regions = {
        'Omega': 'all',
        'Inner': ('vertices by inner_arc', 'facet'),
        'Gamma_c': ('vertices by outer_arc', 'facet'),
        'Symmetry_x': (f'vertices in (x < {tol})', 'facet'),
        'Symmetry_y': (f'vertices in (y < {tol})', 'facet'),
    }

    materials = {
        'solid': ({'D': stiffness_from_youngpoisson(2, E, nu,
                                                    plane='strain')},),
    }

    fields = {
        'displacement': ('real', 'vector', 'Omega', 1),
        'scalar': ('real', 'scalar', 'Omega', 1),  # only for M
    }

    variables = {
        'u': ('unknown field', 'displacement', 0),
        'v': ('test field', 'displacement', 'u'),
        'p': ('unknown field', 'scalar', 1),
        'q': ('test field', 'scalar', 'p'),
    }

    def pushed_out(ts, coors, **kwargs):
        """u = δ x / a on the inner arc: radially outwards by δ."""
        return delta * coors / a

    functions = {
        'inner_arc': (inner_arc,),
        'outer_arc': (outer_arc,),
        'pushed_out': (pushed_out,),
    }

    ebcs = {
        'mandrel': ('Inner', {'u.all': 'pushed_out'}),
        'symmetry_x': ('Symmetry_x', {'u.0': 0.0}),
        'symmetry_y': ('Symmetry_y', {'u.1': 0.0}),
    }

    integrals = {
        'i': 2,
    }

    equations = {
        'balance_of_forces': 'dw_lin_elastic.i.Omega(solid.D, v, u) = 0',
    }

    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', dict(export.NO_SOLVE)),
    }

    return locals()


if __name__ == '__main__':
    sys.exit(export.main(__file__))
