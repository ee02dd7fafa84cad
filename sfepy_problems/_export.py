r"""Shared export of SfePy problems to the contact solver's ``.npz`` format.

Used by the problem files in this folder (``block_obstacle.py``,
``hertz_cylinder.py``, ...) from their ``post_process_hook_final``, from
their ``define()`` (:func:`set_verbosity`) and when they are run as
scripts (:func:`main`); they load this file by path. The leading
underscore marks it as a helper, not a problem file for ``sfepy-run``.
Installed (``pip install .``), its public names are
:mod:`sfepy_problems.export`, which problem files elsewhere import
(``docs/own-problem.md``).

**Quiet by default.** An export prints one line, ``exported N DOFs, Nc
contact nodes -> PATH`` (and errors). SfePy's messages (the problem set-up,
the ``left over:`` keys of ``define()``, the log of its own linear solve) are
switched off in ``define()`` unless asked for: ``-d "..., verbose=True"`` or
the environment variable ``CONTACT_SSN_VERBOSE=1``. One more notice cannot be
switched off from a problem file: without jax installed, SfePy prints
``install jax and jaxlib to use terms_jax.py!`` and three ``sfepy:`` lines
when it imports its optional JAX terms, i.e. when ``sfepy-run`` starts,
before any problem file is read. Running the problem file as a script,
``python sfepy_problems/FILE.py -d "..."`` (:func:`main`, the same options
as ``sfepy-run``), drops exactly that notice; there ``-v`` shows everything.

What is exported (``docs/npz-format.md``):

* **K**, the stiffness reduced to the free DOFs: the weak-mode matrix of the
  stiffness term with the Dirichlet conditions applied (SfePy's "active"
  DOFs). It equals :math:`K_{full}[F, F]` with F the free DOFs (checked by
  ``tests/test_hertz.py``).
* **f**, the reduced load including the lifting of non-zero Dirichlet
  values. With :math:`u = u_F + u_D` (:math:`u_D` the prescribed values,
  zero at free DOFs), the free rows of :math:`K_{full} u = f_{ext}` read

  .. math::  K_{FF}\, u_F = f_{ext,F} - (K_{full}\, u_D)_F \;,

  so ``f = f_ext[F] - (K_full u_D)[F]``. :math:`K_{full}` is assembled
  without any Dirichlet conditions (:func:`full_stiffness`); the subtraction
  is skipped when :math:`u_D = 0`, so that f is then exactly
  :math:`f_{ext,F}`.
* **u_prescribed**, the Dirichlet values per node and component.
* **contact_nodes**, the vertices of the facet region Γc, and their reduced
  DOFs. In 2D ordered along the boundary
  (:func:`solver.geometry.mesh.order_along_boundary`; a Γc of separate
  parts, chain after chain); in 3D in increasing
  node number, with **contact_faces**, the facets of Γc as triangles oriented
  outward (:func:`contact_triangles`).
* **M**, :math:`M_{ij} = \int_{\Gamma_c} \varphi_i \varphi_j` for the scalar
  P1 field, assembled over the whole mesh and restricted to the contact nodes
  in their order.

**Two bodies** (format version 4, 2D; issue 19; :func:`two_body_keys`):
one mesh with a cell region per body that share no node, ``mortar=dict(
slave=..., master=..., bodies=[...])`` naming the slave and master facet
regions and the bodies' cell regions (index = body id). Exported: ``body``
per node, the facets of the two regions as segments oriented with their
body on the left (``mortar_slave``, ``mortar_master``), contact_nodes = the
slave chain in the segments' direction, M on the slave region, no obstacle.

**2D and 3D.** The dimension d is the mesh's. Full field DOF numbers are
``d * node + component``, nodal arrays have d columns, the cells are SfePy's
``'2_3'`` triangles, ``'2_4'`` quadrilaterals, ``'3_4'`` tetrahedra or
``'3_8'`` hexahedra, one kind per mesh (:func:`mesh_cells`; issue 35), and
the contact faces of a hexahedral mesh quadrilaterals. In 3D a problem file exports
*without* SfePy's own solve (:func:`export_only`, or ``sfepy-run`` with the
no-solve Newton settings :data:`NO_SOLVE`): its direct solve of the
elasticity problem alone takes minutes at 10⁴–10⁵ DOFs, and nothing of it is
exported.
"""
import contextlib
import io
import os
import re
import sys

import numpy as nm

from solver.geometry.mesh import order_along_boundary
from solver.problem import ContactProblem, save_problem

__all__ = ['export_contact_problem', 'obstacle_curve', 'reduced_system',
           'full_stiffness', 'stage_loads', 'contact_triangles',
           'mesh_cells',
           'two_body_keys', 'save_displacement',
           'export_only', 'solve_only', 'NO_SOLVE',
           'set_verbosity', 'main', 'VERBOSE_ENV']

#: ``nls.newton`` settings that stop before the first linear solve: the
#: residual of the initial state is evaluated (cheap) and accepted
#: (``eps_a`` = ∞), so ``sfepy-run`` reaches ``post_process_hook_final``
#: without factorising K. The 3D problem files use them.
NO_SOLVE = {'i_max': 0, 'eps_a': float('inf'), 'eps_r': 1.0}

#: Environment variable that makes exports verbose (any value but '' or '0').
VERBOSE_ENV = 'CONTACT_SSN_VERBOSE'

#: What SfePy prints when it imports ``sfepy/terms/terms_jax.py`` without jax
#: (a ``print`` in that module, then ``load_classes``'s warning).
JAX_NOTICE = re.compile(
    r"install jax and jaxlib to use terms_jax\.py!\n"
    r"sfepy: WARNING: module \S*terms_jax\.py cannot be imported!\n"
    r"sfepy: reason:\n No module named 'jax[\w.]*'\n")

_silenced = False  # whether set_verbosity() switched SfePy's output off


def set_verbosity(verbose=None):
    """Switch SfePy's screen messages off, unless ``verbose``.

    Called first in the problem files' ``define()``, so that it also covers
    the ``left over:`` message SfePy prints right after ``define()``, the
    set-up and the log of SfePy's own solve. ``verbose=None`` reads
    :data:`VERBOSE_ENV`. Only plain screen output is switched off: with
    ``sfepy-run -q`` or ``--log FILE`` SfePy's own setting is kept.

    Returns
    -------
    bool
        The verbosity in force.
    """
    global _silenced
    from sfepy.base.base import output

    if verbose is None:
        verbose = os.environ.get(VERBOSE_ENV, '') not in ('', '0')
    verbose = bool(verbose)
    if not verbose:
        if output.output_function.__name__ == 'output_screen':
            output.set_output(quiet=True)
            _silenced = True
    elif _silenced:  # an earlier quiet export in this process
        output.set_output()
        _silenced = False
    return verbose


def _import_sfepy_run(verbose):
    """``sfepy.scripts.simple.main``, imported without SfePy's jax notice.

    Everything the import prints except :data:`JAX_NOTICE` is passed on.
    """
    if verbose:
        from sfepy.scripts.simple import main as sfepy_run
        return sfepy_run
    captured = io.StringIO()
    try:
        with contextlib.redirect_stdout(captured):
            from sfepy.scripts.simple import main as sfepy_run
    finally:
        sys.stdout.write(JAX_NOTICE.sub('', captured.getvalue()))
    return sfepy_run


def main(problem_file, argv=None):
    """``python sfepy_problems/FILE.py ARGS``: ``sfepy-run FILE ARGS``, quiet.

    ARGS are ``sfepy-run``'s options (``-d "mesh='...', output='...'"``,
    ``-o``, ...) plus ``-v``/``--verbose``, which shows SfePy's messages
    (it sets :data:`VERBOSE_ENV`). Without ``-v`` the run prints only the
    export line; the jax notice SfePy prints at its import is dropped.

    Returns the exit code: 0, or 1 when the export fails. Then, without
    ``-v``, one line ``FILE.py: error: ...`` goes to stderr instead of a
    traceback (a missing mesh, a region that selects nothing, a hook's
    ``ValueError``: almost always bad input); with ``-v`` the exception is
    raised, as ``sfepy-run`` does.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    verbose = any(arg in ('-v', '--verbose') for arg in argv)
    argv = [arg for arg in argv if arg not in ('-v', '--verbose')]
    if verbose:
        os.environ[VERBOSE_ENV] = '1'
    sfepy_run = _import_sfepy_run(verbose)
    sys.argv = ['sfepy-run', os.path.abspath(problem_file)] + argv
    try:
        return sfepy_run() or 0
    except Exception as exc:
        if verbose:
            raise
        message = ' '.join(str(exc).split()) or type(exc).__name__
        print(f'{os.path.basename(problem_file)}: error: {message} (-v shows '
              'the traceback)', file=sys.stderr)
        return 1


def full_stiffness(pb, stiffness):
    """The stiffness matrix over all DOFs, without Dirichlet conditions.

    ``active_only=False`` alone is not enough: SfePy then still drops the
    rows and columns of the Dirichlet DOFs of the equations' variables (they
    come out zero), so the variables are set up with no conditions at all
    (``ebcs=Conditions([])``). Rows/columns: full field DOFs
    ``d * node + component``.
    """
    from sfepy.discrete.conditions import Conditions

    return pb.evaluate(stiffness, mode='weak', dw_mode='matrix',
                       copy_materials=False, active_only=False,
                       ebcs=Conditions([]), verbose=False).tocsr()


def reduced_system(pb, u, stiffness, load=None):
    """The reduced stiffness K, load f and the Dirichlet data of ``pb``.

    Parameters
    ----------
    pb : sfepy.discrete.Problem
        The problem after its solve.
    u : sfepy.discrete.FieldVariable
        The displacement variable of the equations (its ``eq_map`` carries
        the Dirichlet conditions), a P1 vector field in 2D or 3D.
    stiffness : str
        The stiffness term, e.g. ``'dw_lin_elastic.i.Omega(solid.D, v, u)'``.
    load : str or None
        The external load term(s) (right-hand side), or None for no load.

    Returns
    -------
    K : scipy.sparse.csr_matrix
        (Ñ, Ñ), Dirichlet DOFs eliminated.
    f : (Ñ,) float array
        ``f_ext[free] - (K_full @ u_D)[free]``.
    eqi : (Ñ,) int array
        Full field DOF (``d * node + component``) of each reduced DOF.
    u_prescribed : (n_nodes, d) float array
        Dirichlet values (0 at free DOFs).
    """
    n_nodes = u.field.n_nod
    K = pb.evaluate(stiffness, mode='weak', dw_mode='matrix',
                    copy_materials=False, verbose=False)
    n_dofs = K.shape[0]
    if load is None:
        f = nm.zeros(n_dofs)
    else:
        f = pb.evaluate(load, mode='weak', dw_mode='vector',
                        copy_materials=False, verbose=False)
        f = nm.asarray(f, dtype=nm.float64)

    eqi = nm.asarray(u.eq_map.eqi, dtype=nm.int64)
    u_prescribed = nm.zeros((n_nodes, u.n_components))
    u_prescribed.ravel()[u.eq_map.eq_ebc] = u.eq_map.val_ebc
    if nm.any(u_prescribed != 0.0):
        K_full = full_stiffness(pb, stiffness)
        f = f - (K_full @ u_prescribed.ravel())[eqi]
    return K.tocsr(), f, eqi, u_prescribed


def stage_loads(pb, u, stiffness, load, stages):
    """Load vectors and Dirichlet values at the ends of load stages.

    Each stage is a dict with ``dirichlet`` = (s_x, s_y[, s_z]), the factors
    of the x, y (and z) Dirichlet values of ``pb`` at the stage end,
    ``load`` = the factor of the external load, ``steps`` and ``friction``
    (multiplier of f_c). Returns the arrays of the ``load_path*`` keys.
    """
    K, f, eqi, u_prescribed = reduced_system(pb, u, stiffness, None)
    f_ext = nm.zeros(len(eqi)) if load is None else nm.asarray(
        pb.evaluate(load, mode='weak', dw_mode='vector',
                    copy_materials=False, verbose=False), dtype=nm.float64)
    K_full = full_stiffness(pb, stiffness)
    path, prescribed = [], []
    for stage in stages:
        u_D = u_prescribed * nm.asarray(stage['dirichlet'], dtype=float)
        path.append(stage['load'] * f_ext - (K_full @ u_D.ravel())[eqi])
        prescribed.append(u_D)
    return dict(load_path=nm.array(path),
                load_path_steps=nm.array([s['steps'] for s in stages],
                                         dtype=nm.int64),
                load_path_friction=nm.array([s['friction'] for s in stages],
                                            dtype=float),
                load_path_prescribed=nm.array(prescribed))


def export_contact_problem(pb, variables, filename, *, stiffness, load=None,
                           obstacle, meta, region='Gamma_c',
                           mass='dw_dot.i.{region}(q, p)', load_path=None,
                           mortar=None):
    """Assemble K, f, M of ``pb`` and write the ``.npz`` problem file.

    Parameters
    ----------
    pb : sfepy.discrete.Problem
        Solved problem with a P1 vector field ``u`` (test ``v``) and a scalar
        P1 field ``p`` (test ``q``) on the whole mesh, used only for M.
    variables : sfepy.discrete.Variables
        The solution variables (the second argument of SfePy's
        ``post_process_hook_final``).
    filename : str
        The ``.npz`` to write.
    stiffness, load : str
        Terms for :func:`reduced_system`.
    obstacle : dict, or the solver's obstacle object
        2D: ``{'x': 'x(t)', 'y': 'y(t)'}``, a parametric curve in t
        (optional ``'t_range'``, ``'search_interval'``: [t0, t1]), or
        ``{'points': [[x0, y0], [x1, y1], ...]}``, a polyline
        (:func:`obstacle_curve`); or a ``ParametricCurve`` /
        ``PolylineCurve``. 3D: a surface spec dict (``{'kind': 'plane',
        ...}``, ``docs/npz-format.md``) or a surface object. None with
        ``mortar``.
    meta : dict
        Problem metadata (E, nu, plane, load, mesh, ...); the SfePy version
        is added to ``meta['versions']``.
    region : str
        The facet region Γc.
    mass : str
        The M term, ``{region}`` is replaced by ``region``.
    load_path : list of dict, optional
        Load stages for friction runs, see :func:`stage_loads`; the last
        stage must end at the full Dirichlet values and load.
    mortar : dict, optional
        Two bodies (:func:`two_body_keys`): ``slave``, ``master`` (facet
        regions) and ``bodies`` (cell regions, index = body id); then
        ``obstacle`` is None and ``region`` is the slave region.

    Returns
    -------
    ContactProblem
        The exported problem.
    """
    import sfepy

    u = variables['u']
    mesh = pb.domain.mesh
    n_nodes = mesh.n_nod
    if u.field.n_nod != n_nodes or not nm.allclose(u.field.get_coor(),
                                                    mesh.coors):
        raise ValueError('P1 field nodes must coincide with mesh vertices')

    dim = mesh.dim
    K, f, eqi, u_prescribed = reduced_system(pb, u, stiffness, load)
    dof_map = nm.stack([eqi // dim, eqi % dim], axis=1).astype(nm.int64)

    cells = mesh_cells(mesh)
    if mortar is not None:
        region = mortar['slave']
    gamma_c = pb.domain.regions[region]
    faces = {}
    if mortar is not None:  # two bodies: the slave chain, no obstacle
        faces = two_body_keys(pb, mortar, cells, mesh.coors)
        contact_nodes = faces.pop('contact_nodes')
    elif dim == 2:  # the vertices of Gamma_c, ordered along the boundary
        # (several chains where it has separate parts, e.g. two sides)
        contact_nodes = order_along_boundary(gamma_c.vertices, cells,
                                             mesh.coors, pieces=True)
    else:  # its triangles (quads), outward; the nodes in increasing order
        faces['contact_faces'] = contact_triangles(pb, region, cells,
                                                   mesh.coors)
        contact_nodes = nm.unique(faces['contact_faces'])
    lookup = nm.full(dim * n_nodes, -1, dtype=nm.int64)
    lookup[eqi] = nm.arange(len(eqi))
    contact_dofs = lookup[dim * contact_nodes[:, None] + nm.arange(dim)]

    # M_ij = int_{Gamma_c} phi_i phi_j (thesis (80)), scalar P1 field, full
    # mesh numbering; keep the Gamma_c rows and columns in chain order.
    M_full = pb.evaluate(mass.format(region=region), mode='weak',
                         dw_mode='matrix', try_equations=False,
                         active_only=False, verbose=False)
    M = M_full.tocsr()[contact_nodes][:, contact_nodes]

    if mortar is None and dim == 2 and isinstance(obstacle, dict):
        obstacle = obstacle_curve(obstacle)
    meta = dict(meta)
    meta['versions'] = dict(meta.get('versions', {}), sfepy=sfepy.__version__)
    extra = {} if load_path is None else stage_loads(pb, u, stiffness, load,
                                                     load_path)
    problem = ContactProblem(
        K=K, f=f, M=M, contact_dofs=contact_dofs,
        nodes=mesh.coors[:, :dim].copy(), cells=cells, dof_map=dof_map,
        u_prescribed=u_prescribed, contact_nodes=contact_nodes,
        obstacle=obstacle, meta=meta, **faces, **extra)
    save_problem(filename, problem)
    print(f'exported {problem.n_dofs} DOFs, {problem.n_contact} contact '
          f'nodes -> {filename}')
    return problem


def obstacle_curve(spec):
    """The 2D obstacle of a spec dict: ``{'x': 'x(t)', 'y': 'y(t)'}``
    (optional ``'t_range'``, ``'search_interval'``) as the solver's
    ``ParametricCurve``, or ``{'points': [[x, y], ...]}`` (optional
    ``'search_interval'``, in arc length) as its ``PolylineCurve``, or
    ``{'curves': [spec, ...]}`` (several obstacles, each spec one of the
    two) as its ``SeveralCurves``. The
    expressions take what the ``.npz`` format takes
    (``docs/npz-format.md``: arithmetic in t, sin, cos, sqrt, ...).
    A dict keeps a problem file free of the solver's class names.

    Raises
    ------
    ValueError
        For a dict that is neither (naming the keys it has and may have).
    """
    from solver.geometry import ParametricCurve, PolylineCurve
    from solver.geometry.curves import SeveralCurves

    keys = set(spec)
    if keys == {'curves'}:
        return SeveralCurves([obstacle_curve(c) for c in spec['curves']])
    if keys >= {'x', 'y'} and keys <= {'x', 'y', 't_range',
                                       'search_interval'}:
        return ParametricCurve(spec['x'], spec['y'],
                               t_range=spec.get('t_range'),
                               search_interval=spec.get('search_interval'))
    if keys >= {'points'} and keys <= {'points', 'search_interval'}:
        return PolylineCurve(spec['points'],
                             search_interval=spec.get('search_interval'))
    raise ValueError(f'obstacle: a 2D obstacle is {{"x": ..., "y": ...}} '
                     f'(optionally "t_range", "search_interval") or '
                     f'{{"points": [...]}} (optionally "search_interval"), '
                     f'got the keys {sorted(keys)}')


def _segments(pb, region, cells, coors):
    """The facets of the 2D facet region ``region`` as segments (a, b) with
    their body on the left of a→b (format v4, ``docs/npz-format.md``)."""
    cmesh = pb.domain.cmesh
    facets = pb.domain.regions[region].facets
    cmesh.setup_connectivity(1, 0)
    cmesh.setup_connectivity(1, 2)
    vertices = cmesh.get_incident(0, facets, 1)
    segments = nm.asarray(vertices, dtype=nm.int64).reshape(-1, 2)
    owner, offsets = cmesh.get_incident(2, facets, 1, ret_offsets=True)
    if not len(segments) or nm.any(nm.diff(offsets) != 1):
        raise ValueError(f'{region}: empty, or a facet bounds two cells '
                         '(not on the surface)')
    # the body lies on the side of its cell's centroid (triangles or
    # quadrilaterals)
    a, b = coors[segments[:, 0], :2], coors[segments[:, 1], :2]
    c = coors[cells[owner], :2].mean(axis=1)
    right = ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]) < 0
    segments[right] = segments[right][:, ::-1]
    return segments


def _chain(segments, cells, coors):
    """The segments as one chain of nodes in their direction (or None if
    they do not form one open chain)."""
    try:
        chain = order_along_boundary(nm.unique(segments), cells, coors)
    except ValueError:
        return None
    n = len(coors)
    known = set((segments[:, 0] * n + segments[:, 1]).tolist())
    if chain[0] * n + chain[1] not in known:
        chain = chain[::-1]
    steps = chain[:-1] * n + chain[1:]
    if len(chain) != len(segments) + 1 or not all(
            int(k) in known for k in steps):
        return None
    return chain


def two_body_keys(pb, mortar, cells, coors):
    """The two-body keys (format version 4) of a problem with the regions
    ``mortar['slave']``, ``mortar['master']`` (facets) and
    ``mortar['bodies']`` (cells, one per body, sharing no node).

    Returns
    -------
    dict
        ``body`` (n_nodes,), ``mortar_slave`` (2D: in chain order; 3D:
        outward triangles, :func:`contact_triangles`), ``mortar_master``
        (2D: in chain order if they form one) and ``contact_nodes`` (2D:
        the slave chain; 3D: the slave triangles' vertices, increasing).
    """
    regions = pb.domain.regions
    body = nm.full(len(coors), -1, dtype=nm.int64)
    for i, name in enumerate(mortar['bodies']):
        vertices = regions[name].vertices
        if nm.any(body[vertices] >= 0):
            raise ValueError(f'{name}: shares nodes with another body')
        body[vertices] = i
    if nm.any(body < 0):
        raise ValueError(f'{int(nm.sum(body < 0))} nodes are in no body '
                         'region')
    if coors.shape[1] == 3 and cells.shape[1] == 4:  # 3D: triangles
        slave, master = (contact_triangles(pb, mortar[side], cells, coors)
                         for side in ('slave', 'master'))
        return dict(body=body, contact_nodes=nm.unique(slave),
                    mortar_slave=slave, mortar_master=master)
    slave = _segments(pb, mortar['slave'], cells, coors)
    chain = _chain(slave, cells, coors)
    if chain is None:
        raise ValueError(f"{mortar['slave']}: the slave facets do not form "
                         'one open chain')
    master = _segments(pb, mortar['master'], cells, coors)
    master_chain = _chain(master, cells, coors)
    if master_chain is not None:
        master = nm.stack([master_chain[:-1], master_chain[1:]], axis=1)
    return dict(body=body, contact_nodes=chain,
                mortar_slave=nm.stack([chain[:-1], chain[1:]], axis=1),
                mortar_master=master)


def mesh_cells(mesh):
    """The cells of a SfePy mesh of one first-order kind (``2_3``, ``2_4``,
    ``3_4``, ``3_8``) as an int64 array in SfePy's (= VTK's) node order.

    Raises
    ------
    ValueError
        For a mesh of several cell kinds or of another kind.
    """
    kinds = list(dict.fromkeys(mesh.descs))
    if len(kinds) != 1 or kinds[0] not in ('2_3', '2_4', '3_4', '3_8'):
        raise ValueError(f'the mesh has cells {kinds}: the export takes one '
                         'kind of first-order cell, 2_3 or 2_4 (2D), 3_4 '
                         'or 3_8 (3D) (SfePy builds a field on one '
                         'reference geometry only)')
    return mesh.get_conn(kinds[0]).astype(nm.int64)


def contact_triangles(pb, region, cells, coors):
    """The facets of the 3D facet region ``region`` as triangles (of
    tetrahedra) or quadrilaterals (of hexahedra), global node ids, oriented
    outward: the right-hand normal, (x1 − x0) × (x2 − x0) for a triangle,
    (x2 − x0) × (x3 − x1) for a quadrilateral, points away from the centre
    of the one cell each facet bounds.

    Raises
    ------
    ValueError
        If a facet of the region is not on the surface (it bounds two
        cells).
    """
    cmesh = pb.domain.cmesh
    facets = pb.domain.regions[region].facets
    cmesh.setup_connectivity(2, 0)
    cmesh.setup_connectivity(2, 3)
    vertices, offsets = cmesh.get_incident(0, facets, 2, ret_offsets=True)
    width = 4 if cells.shape[1] == 8 else 3
    if nm.any(nm.diff(offsets) != width):
        raise ValueError(f'{region}: the facets are not '
                         + ('quadrilaterals' if width == 4 else 'triangles'))
    faces = nm.asarray(vertices, dtype=nm.int64).reshape(-1, width)
    owner, offsets = cmesh.get_incident(3, facets, 2, ret_offsets=True)
    if nm.any(nm.diff(offsets) != 1):
        raise ValueError(f'{region}: a facet bounds two cells (not on the '
                         'surface)')
    p = coors[faces]
    if width == 3:
        normal = nm.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    else:
        normal = nm.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    centre = coors[cells[owner]].mean(axis=1)
    inward = nm.einsum('ij,ij->i', normal, centre - p.mean(axis=1)) > 0
    faces[inward] = faces[inward][:, [0] + list(range(width - 1, 0, -1))]
    return faces


def save_displacement(pb, variables, filename):
    """Write SfePy's own solution (a problem file's penalty mode) as
    ``.npz``: ``u`` the nodal displacement (n, d), ``coors`` the nodes, and
    the Newton status of the solve (``n_iter``, ``condition``: 0 converged,
    1 not; ``err0``, ``err`` the residual norms; ``time`` SfePy's Newton
    time in seconds) where SfePy keeps it, NaN otherwise.

    Returns the dict written."""
    u = variables['u']
    solver = pb.get_solver()
    status = getattr(getattr(solver, 'nls', solver), 'status', None)

    def get(key):
        return getattr(status, key, nm.nan)

    times = get('time_stats')
    data = dict(u=u().reshape(-1, u.n_components), coors=pb.domain.mesh.coors,
                n_iter=get('n_iter'), condition=get('condition'),
                err0=get('err0'), err=get('err'),
                time=sum(times.values()) if isinstance(times, dict)
                else nm.nan)
    nm.savez(filename, **data)
    print(f"SfePy's solve: {data['n_iter']} Newton iterations, condition "
          f"{data['condition']} -> {filename}")
    return data


def _problem(problem_file, define_args, init_solvers):
    """SfePy's problem of ``problem_file`` built with
    ``define(**define_args)``, and its configuration."""
    from sfepy.base.conf import ProblemConf, get_standard_keywords
    from sfepy.discrete import Problem

    required, other = get_standard_keywords()
    conf = ProblemConf.from_file(os.fspath(problem_file), required, other,
                                 define_args=define_args)
    return Problem.from_conf(conf, init_solvers=init_solvers), conf


def solve_only(problem_file, state0=None, **define_args):
    """SfePy's own solve of a problem file (in-process, as ``sfepy-run``
    does, e.g. the penalty mode of ``sfepy_contact_*.py``), without its
    output files. ``state0``: the start of SfePy's Newton, the nodal
    displacement (n, d) (default zero): a continuation, e.g. from the
    solution at a smaller penalty, where SfePy's Newton from zero fails.

    Returns
    -------
    (variables, status, sfepy.discrete.Problem)
        The solution variables, SfePy's Newton status (``n_iter``,
        ``condition``: 0 converged, ``err0``, ``err``, ``time_stats``) and
        SfePy's problem.
    """
    from sfepy.base.base import IndexedStruct

    pb, _ = _problem(problem_file, define_args, init_solvers=True)
    status = IndexedStruct()
    if state0 is not None:  # a copy: SfePy's Newton writes into it
        state0 = nm.array(state0, dtype=float).ravel()
    variables = pb.solve(state0=state0, status=status, save_results=False)
    return variables, status.nls_status, pb


def export_only(problem_file, **define_args):
    """Export a problem file without solving anything (in-process).

    Builds the SfePy problem of ``problem_file`` with ``define(**define_args)``
    and ``init_solvers=False``, applies its Dirichlet conditions and calls its
    ``post_process_hook_final`` on the initial state: K, f and M are
    assembled, no linear system is solved. What ``sfepy-run`` does with the
    :data:`NO_SOLVE` settings, without the solver objects.

    Returns
    -------
    (ContactProblem or None, sfepy.discrete.Problem)
        What the hook returns (the 3D problem files return the problem
        written; the 2D ones nothing) and SfePy's problem.
    """
    pb, conf = _problem(problem_file, define_args, init_solvers=False)
    pb.time_update()
    variables = pb.get_initial_state()
    variables.apply_ebc()
    hook = conf.options.post_process_hook_final
    if isinstance(hook, str):
        hook = conf.get_function(hook)
    return hook(pb, variables), pb
