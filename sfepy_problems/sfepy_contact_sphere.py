r"""
SfePy's ``elastic_contact_sphere.py`` as a problem of the contact solver:
a unit cube indented by a rigid sphere (issue 35).

SfePy's example (``sfepy/examples/linear_elasticity/
elastic_contact_sphere.py``) presses the sphere of centre C = (0, 0, 1) and
radius R = 0.8 into the top z = 0.5 of the cube [−0.5, 0.5]³ (its mesh
``meshes/3d/cube_medium_hexa.mesh``, 10 × 10 × 10 hexahedra, in SfePy's data
folder); the cube is fixed on its bottom z = −0.5, the material is
isotropic with the Lamé parameters λ = 5.769, μ = 3.846 (E = 10, ν = 0.3).
The sphere's lowest point z = 0.2 lies 0.3 below the top: the indentation
is the initial overlap of the sphere and the cube.

SfePy solves

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    + \int_{\Gamma} \ul{v} \cdot f(d(\ul{u})) \ul{n}(\ul{u}) = 0
    \;, \quad \forall \ul{v} \;,

a *penalty*: at the quadrature points of the top face (order 6) in their
*deformed* position X + u, the penetration d = R − |X + u − C| gives the
force f(d) = k d + f₀ along the deformed normal n(u) (k = 1e5, f₀ = 1e-2,
smoothed to 0 over −2f₀/k < d ≤ 0). The contact solver solves the same
body *exactly*: u_n ≤ s, λ ≥ 0, λ (s − u_n) = 0 at the *nodes* of Γc = the
top face, the gap s and the normal fixed in the *reference* position
(the obstacle ``{"kind": "sphere", "center": [0, 0, 1], "radius": 0.8}``,
gaps along its normals). ``notebooks/sfepy_examples.ipynb`` measures the
three differences.

By default SfePy solves nothing here (the export runs on the initial state,
``_export.NO_SOLVE``); ``penalty=k`` instead solves SfePy's own penalty
problem of the example on the same mesh (with ``f0``, SfePy's Newton
settings of the example, ``i_max`` its iterations at most) and writes its
displacement as ``.npz`` (keys ``u``, the nodal displacement (n, 3), and
``coors``) to ``output``; ``penalty=1e5`` is SfePy's example itself; ``quadrature='nodes'``
moves its quadrature points to the faces' vertices
(``_sfepy_example.QUADRATURES``).

Usage (from the repository root)::

  sfepy-run sfepy_problems/sfepy_contact_sphere.py \
      -d "output='output/sfepy_contact_sphere.npz'"
  python -m solver output/sfepy_contact_sphere.npz
  sfepy-run sfepy_problems/sfepy_contact_sphere.py \
      -d "penalty=1e5, output='output/sfepy_contact_sphere_penalty.npz'"

The first prints ``exported 3630 DOFs, 121 contact nodes -> PATH``.
Parameters (``-d``): ``mesh`` (default SfePy's ``cube_medium_hexa.mesh``),
``output``, ``penalty``, ``f0``, ``i_max``, ``quadrature``, ``verbose``.
"""
import importlib.util
import os.path as op
import sys


def _load_common():
    """``sfepy_problems/_sfepy_example.py`` by path (this folder is not a
    package): what the two SfePy examples share."""
    name = '_contact_ssn_sfepy_example'
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, op.join(op.dirname(op.abspath(__file__)),
                          '_sfepy_example.py'))
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


common = _load_common()
#: The example's sphere and its force at zero penetration.
CENTRE, RADIUS = [0.0, 0.0, 1.0], 0.8
F0 = 1e-2


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: the ``.npz`` of the contact solver, or
    SfePy's penalty displacement (``_sfepy_example.export``)."""
    return common.export(
        pb, variables,
        obstacle={'kind': 'sphere', 'center': CENTRE, 'radius': RADIUS},
        meta={'load': {'sphere_overlap': 0.3},
              'problem_file': 'sfepy_problems/sfepy_contact_sphere.py',
              'description': "SfePy's elastic_contact_sphere.py: the cube "
                             '[-0.5, 0.5]^3 indented 0.3 by the rigid '
                             'sphere |x - (0, 0, 1)| <= 0.8'})


def define(mesh=common.MESH, output='output/sfepy_contact_sphere.npz',
           penalty=None, f0=F0, i_max=common.NEWTON['i_max'],
           quadrature='gauss', verbose=None):
    return common.problem(
        export_contact_problem, mesh, output, penalty, i_max, quadrature,
        verbose,
        contact_materials={'cs': ({'f': [penalty or common.K_PENALTY, f0],
                                   '.c': CENTRE, '.r': RADIUS},)},
        contact_terms=['dw_contact_sphere.ic.Top(cs.f, cs.c, cs.r, v, u)'])


if __name__ == '__main__':
    sys.exit(common.load_export().main(__file__))
