r"""
SfePy's ``elastic_contact_planes.py`` as a problem of the contact solver:
a unit cube indented by a rigid pyramid of four bounded planes (issue 35).

SfePy's example (``sfepy/examples/linear_elasticity/
elastic_contact_planes.py``) presses four planes into the top z = 0.5 of
the cube [−0.5, 0.5]³ (its mesh ``meshes/3d/cube_medium_hexa.mesh``,
10 × 10 × 10 hexahedra, in SfePy's data folder), fixed on its bottom
z = −0.5; λ = 5.769, μ = 3.846 (E = 10, ν = 0.3). Plane i passes through
the anchor A = (0, 0, 0.3) with the normal n_i = (±0.3, 0, 1) or
(0, ±0.3, 1) (pointing into the obstacle) and acts only where a point's
orthogonal projection onto it falls into the projection of a triangle
``bs`` (A and two corners of the square |x|, |y| ≤ 0.25 at z = 0.3): the
four faces of a pyramid, apex down at A, 0.2 below the top.

SfePy solves

.. math::
    \int_{\Omega} D_{ijkl}\ e_{ij}(\ul{v}) e_{kl}(\ul{u})
    + \sum_{i=1}^4 \int_{\Gamma} \ul{v} \cdot f(d_i(\ul{u})) \ul{n}_i = 0
    \;, \quad \forall \ul{v} \;,

a *penalty* at the quadrature points (order 6) of the top: the penetration
d_i = (X + u − A)·n_i of the *deformed* point, the force f(d) = k d + f₀
(k = 1e5, f₀ = 1e2, smoothed to 0 over −2f₀/k < d ≤ 0), the bounds tested
on the reference point. The contact solver solves the same body *exactly*
at the *nodes* of Γc = the top, gaps in the *reference* position, against
``{"kind": "several", "surfaces": [four "polygon"s]}``: each polygon SfePy's
plane (anchor, ``-n_i``, the vertices ``bs``), each node taking the plane of
smallest gap among those whose polygon it projects into (the same mask as
SfePy's). On this mesh 9 nodes of the top, x, y ∈ {−0.1, 0, 0.1}, project
into a polygon; those at ±0.2 fall just outside (the triangles' projections
end at |x| = 0.229 on the planes, a node's foot at 0.2385).
``notebooks/sfepy_examples.ipynb`` measures the differences.

By default SfePy solves nothing here (``_export.NO_SOLVE``); ``penalty=k``
solves SfePy's own penalty problem on the same mesh (``f0``; the example's
Newton settings, ``i_max`` iterations at most) and writes its displacement
as ``.npz`` (``u``, ``coors``, SfePy's Newton status) to ``output``;
``penalty=1e5`` is SfePy's example itself; ``quadrature='nodes'``
moves its quadrature points to the faces' vertices
(``_sfepy_example.QUADRATURES``).

Usage (from the repository root)::

  sfepy-run sfepy_problems/sfepy_contact_planes.py \
      -d "output='output/sfepy_contact_planes.npz'"
  python -m solver output/sfepy_contact_planes.npz
  sfepy-run sfepy_problems/sfepy_contact_planes.py \
      -d "penalty=1e5, output='output/sfepy_contact_planes_penalty.npz'"

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
#: The example's planes: normal components, polygon size, anchor height.
DN, DS, AZ = 0.3, 0.25, 0.3
#: Per plane: SfePy's normal n (into the obstacle) and boundary points bs.
PLANES = [([DN, 0.0, 1.0], [[0.0, 0.0, AZ], [-DS, -DS, AZ], [-DS, DS, AZ]]),
          ([-DN, 0.0, 1.0], [[0.0, 0.0, AZ], [DS, -DS, AZ], [DS, DS, AZ]]),
          ([0.0, DN, 1.0], [[0.0, 0.0, AZ], [-DS, -DS, AZ], [DS, -DS, AZ]]),
          ([0.0, -DN, 1.0], [[0.0, 0.0, AZ], [-DS, DS, AZ], [DS, DS, AZ]])]
#: The example's force at zero penetration.
F0 = 1e2


def obstacle():
    """The four planes as ``several`` ``polygon``s: SfePy's anchor, its
    normal reversed (the project's points out of the obstacle), its
    boundary points."""
    return {'kind': 'several', 'surfaces': [
        {'kind': 'polygon', 'point': [0.0, 0.0, AZ],
         'normal': [-c for c in normal], 'vertices': bounds}
        for normal, bounds in PLANES]}


def export_contact_problem(pb, variables):
    """``post_process_hook_final``: the ``.npz`` of the contact solver, or
    SfePy's penalty displacement (``_sfepy_example.export``)."""
    return common.export(
        pb, variables, obstacle=obstacle(),
        meta={'load': {'pyramid_apex_depth': 0.5 - AZ},
              'problem_file': 'sfepy_problems/sfepy_contact_planes.py',
              'description': "SfePy's elastic_contact_planes.py: the cube "
                             '[-0.5, 0.5]^3 indented by a rigid pyramid of '
                             'four bounded planes, apex 0.2 deep'})


def define(mesh=common.MESH, output='output/sfepy_contact_planes.npz',
           penalty=None, f0=F0, i_max=common.NEWTON['i_max'],
           quadrature='gauss', verbose=None):
    materials = {f'cp{i}': ({'f': [penalty or common.K_PENALTY, f0],
                             '.n': normal, '.a': [0.0, 0.0, AZ],
                             '.bs': bounds},)
                 for i, (normal, bounds) in enumerate(PLANES)}
    terms = [f'dw_contact_plane.ic.Top(cp{i}.f, cp{i}.n, cp{i}.a, cp{i}.bs, '
             'v, u)' for i in range(len(PLANES))]
    return common.problem(
        export_contact_problem, mesh, output, penalty, i_max, quadrature,
        verbose, contact_materials=materials, contact_terms=terms)


if __name__ == '__main__':
    sys.exit(common.load_export().main(__file__))
