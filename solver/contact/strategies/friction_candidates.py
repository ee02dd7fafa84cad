r"""Coulomb friction condensed onto the candidate nodes.

The condensed friction run works on the Schur complement S of K on every
DOF of Γc: in 3D a dense (3Nc)² matrix whose Newton systems cost (5Nc)³.
A node that never touches carries no force (λ = 0, so the Coulomb disc
has radius 0 and t = 0), so only the d DOFs of the *candidates* need to
stay: the same run on their geometry, S of size 3m, m ≪ Nc.

Choosing them: the frictionless problem at the final load, on the normal
candidates (:mod:`.candidates`; Wriggers's screening), gives every
node's remaining gap and contact set; the first friction candidates
are that set and :data:`RINGS` rings of its neighbours along the contact
triangles, or the nodes with s − u_n ≤ ``margin`` (default
:data:`RING_FRACTION` of its range). In 3D the screening condenses K onto
every free DOF of its candidates
(:class:`~.candidates.NodalCondensation`): the friction candidates lie
within them, and the friction run's S is then a dense Schur complement
of that S (:class:`~solver.linalg.SubCondensation`), K factorised once. Each load step's non-candidates are
checked as the step is delivered; a penetration enlarges the set and the
run **restarts from the first step**: friction is path-dependent, and the
new candidates then share the full problem's history (the zero state).
A step whose non-candidates all keep s − u_n ≥ 0 solves the full
problem's step exactly (there λ = 0, t = 0, and the condensation is exact
for forces on the candidates only). Delivered steps are not delivered
twice; a failure may be found up to a :data:`~solver.contact.friction.
stream.BATCH` late. After :data:`~.candidates.MAX_ROUNDS` rounds the last
run takes every node. The disc: Hüeber, Stadler & Wohlmuth, SIAM J. Sci.
Comput. 30 (2008) 572-596."""

import time

import numpy as np
import scipy.sparse as sp

from ...ncp import stable_norm
from ..frictionless.driver import run_frictionless
from ..geometry import contact_stiffness
from .candidates import MAX_ROUNDS, enlarge_candidates, initial_candidates
from ..verify import (contact_scale, verification_tolerance, verify_contact,
                      verify_excluded, worst_verification)

__all__ = ["RING_FRACTION", "RINGS", "use_candidates", "remaining_gap",
           "first_candidates", "surface_adjacency", "friction_on_candidates"]


class _Penetration(Exception):
    """A non-candidate penetrates after load step ``step``."""

    def __init__(self, step, remaining, length):
        super().__init__(step)
        self.step, self.remaining, self.length = step, remaining, length


def remaining_gap(geometry, u):
    """s − u_n at every node of ``geometry`` for reduced u (its component
    DOFs ``node_dofs``; −1, a Dirichlet component, reads 0)."""
    padded = np.append(np.asarray(u, float), 0.0)
    return geometry.gap - np.einsum("ij,ij->i", geometry.normal,
                                    padded[geometry.node_dofs])


#: Default ring of the friction candidates: nodes whose frictionless
#: remaining gap is at most this fraction of its range over Γc.
RING_FRACTION = 0.01


#: Rings of contact-surface neighbours around the screening's contact set
#: in the first friction candidates (module docstring).
RINGS = 2


def first_candidates(remaining, margin=None, contact=None, adjacency=None):
    """The first friction candidates (positions) from the frictionless
    remaining gaps s − u_n at the final load, and δ: with ``margin`` None,
    ``contact`` (bool, the screening's contact set) and ``adjacency``
    (:func:`surface_adjacency`), that set and :data:`RINGS` rings of its
    neighbours (δ: the largest s − u_n among them); else those with
    s − u_n ≤ δ (``margin``, default :data:`RING_FRACTION` of the range)."""
    if margin is None and adjacency is not None and contact is not None \
            and np.any(contact):
        chosen = np.asarray(contact, bool)
        for _ in range(RINGS):
            chosen = chosen | (adjacency @ chosen.astype(float) > 0)
        nodes = np.flatnonzero(chosen)
        return nodes, float(np.max(remaining[nodes]))
    if margin is None:
        margin = RING_FRACTION * float(np.ptp(remaining)) if len(remaining) \
            else 0.0
    return np.flatnonzero(remaining <= margin), float(margin)


def surface_adjacency(problem, geometry):
    """Sparse (Nca, Nca) adjacency of ``geometry``'s nodes along the
    edges of the contact triangles ``problem.contact_faces`` (node ids),
    or None if the problem has none (2D, discrete)."""
    faces = getattr(problem, "contact_faces", None)
    if faces is None or not len(faces):
        return None
    faces = np.asarray(faces)
    ids = np.asarray(problem.contact_nodes)[geometry.index]
    lookup = np.full(max(int(faces.max()), int(ids.max(initial=0))) + 1, -1)
    lookup[ids] = np.arange(len(ids))
    a, b = lookup[faces], lookup[np.roll(faces, -1, axis=1)]
    a, b = a.ravel(), b.ravel()
    keep = (a >= 0) & (b >= 0)  # supports are not in the geometry
    a, b = a[keep], b[keep]
    n = len(ids)
    return sp.csr_matrix((np.ones(2 * len(a)), (np.concatenate([a, b]),
                                                np.concatenate([b, a]))),
                         shape=(n, n))


def friction_on_candidates(solve, problem, friction, geometry, engine,
                           margin, kwargs):
    """The friction driver (``solve``, :func:`~solver.contact.friction.
    driver.run_friction`) on the candidates of ``geometry`` (module
    docstring), ``kwargs`` its other arguments (``gap_scale`` that of the
    whole Γc). Returns its result over every node of Γc (non-candidates:
    λ = 0, t = 0), ``verification`` including every node's gap,
    ``condensation`` "candidates" and ``candidates``: ``margin`` δ₀,
    ``rounds`` (``stage``, ``n_candidates``, ``penetrating``, the ``step``
    that failed the check or None, ``time``), ``n_candidates``, ``enlarged``.
    """
    start = time.perf_counter()
    kwargs = dict(kwargs)
    on_step, progress = kwargs.pop("on_step"), kwargs.pop("progress")
    keep = kwargs.get("keep_steps", True)
    tol = kwargs.get("tol", 1e-10)
    tol_v = verification_tolerance(tol)
    stiffness = contact_stiffness(problem.K, geometry)
    load_norm = stable_norm(problem.f)
    final = problem.f if problem.load_path is None else problem.load_path[-1]
    everyone = np.arange(len(geometry.gap))
    rounds = []
    clock = time.perf_counter()
    screen = run_frictionless(  # step 1: the final load, no friction
        problem, geometry, engine, kwargs.get("method", "fb"),
        tol=tol, max_iter=kwargs.get("max_iter", 100),
        gap_scale=kwargs["gap_scale"], options=kwargs.get("options"),
        condense=True, start="free", candidates=True,
        nodal=geometry.dim == 3 and getattr(engine, "nodal_condensation",
                                            False))
    nodes, delta = first_candidates(
        remaining_gap(geometry, screen.u), margin,
        screen.in_contact[geometry.index], surface_adjacency(
            problem, geometry)) if screen.success else ((), 0.0)
    if not len(nodes):  # no contact at the final load: the gaps alone
        nodes, delta = initial_candidates(geometry.gap)
    rounds.append(dict(stage="screening", n_candidates=len(nodes),
                       step=None, penetrating=0,
                       time=time.perf_counter() - clock))

    def grow(remaining, length, step, clock):
        """The next set after a penetration at ``step`` (every node once
        the rounds are spent); records the round."""
        outside = np.setdiff1d(everyone, nodes)
        rounds.append(dict(stage="steps", n_candidates=len(nodes), step=step,
                           penetrating=int(np.count_nonzero(
                               remaining[outside] < -length)),
                           time=time.perf_counter() - clock))
        if len(rounds) >= MAX_ROUNDS:
            return everyone
        return enlarge_candidates(nodes, remaining, length)

    sent, reported, last = [0], [0], {}
    # a step's progress record waits for its check (the checks come in
    # batches of recovered steps, StepStream): a round that a penetration
    # ends is then never reported, and the progress lines count the
    # nodes in contact of the round whose steps make the result
    records, checked = {}, set()

    def check(fields):
        """on_step of the run: the non-candidates' gaps, then delivery."""
        last["count"] = last.get("count", 0) + 1
        lam = fields["contact_force"][geometry.index]
        remaining = remaining_gap(geometry, fields["u"])
        length = tol_v * contact_scale(load_norm, lam) / stiffness
        outside = np.setdiff1d(everyone, nodes)
        if np.any(remaining[outside] < -length):
            raise _Penetration(last["count"], remaining, length)
        last["fields"] = fields
        checked.add(last["count"])
        release()
        if last["count"] > sent[0]:
            sent[0] = last["count"]
            if on_step is not None:
                on_step(_fill(fields, geometry, outside))

    def report(record):
        records[record["step"]] = record
        release()

    def release():
        """Report, in order, the steps both recorded and checked."""
        step = reported[0] + 1
        while step in records and step in checked:
            reported[0] = step
            if progress is not None:
                progress(records.pop(step))
            step += 1

    while True:
        clock = time.perf_counter()
        last.clear()
        records.clear(), checked.clear()
        try:
            result = solve(problem, geometry.subset(nodes), engine, friction,
                           condense=True, candidates=False, on_step=check,
                           progress=report, **kwargs)
        except _Penetration as failure:
            nodes = grow(failure.remaining, failure.length, failure.step,
                         clock)
            continue
        rounds.append(dict(stage="steps", n_candidates=len(nodes), step=None,
                           penetrating=0, time=time.perf_counter() - clock))
        break
    _complete(result, problem, geometry, nodes, last.get("fields"), final,
              stiffness, tol_v, keep)
    result.update(condensation="candidates", time=time.perf_counter() - start,
                  candidates=dict(margin=delta, rounds=rounds,
                                  n_candidates=len(nodes),
                                  enlarged=sum(r["penetrating"] > 0
                                               for r in rounds)))
    return result


def _tangential(geometry, outside, u):
    """Tangential displacements (…, k, d − 1) of the nodes ``outside`` for
    reduced u (…, Ñ): the tangents on the node's own DOFs ``node_dofs``
    (a roller's Dirichlet component reads 0, so its e_c component is 0, as
    the load step's system gives)."""
    u = np.asarray(u, float)
    padded = np.concatenate([u, np.zeros(u.shape[:-1] + (1,))], axis=-1)
    return np.einsum("ikj,...ij->...ik", geometry.tangents[outside],
                     padded[..., geometry.node_dofs[outside]])


def _fill(fields, geometry, outside):
    """A step's fields with the non-candidates' tangential displacement
    (NaN in the run on the candidates' geometry), in place."""
    ut = fields["tangential_displacement"]
    ut[geometry.index[outside]] = _tangential(geometry, outside,
                                              fields["u"]).reshape(
        (len(outside),) + ut.shape[1:])
    return fields


def _complete(result, problem, geometry, nodes, fields, final, stiffness,
              tol_v, keep):
    """Every node's gap, normal (and kept tangential displacements) in
    ``result``; its verification merged with the last step's check on
    every node of Γc against the original K and f."""
    outside = np.setdiff1d(np.arange(len(geometry.gap)), nodes)
    result.gap[geometry.index] = geometry.gap
    result.normal[geometry.index] = geometry.normal
    if keep and result.steps_completed:
        ut = result.tangential_displacement
        ut[:, geometry.index[outside]] = _tangential(
            geometry, outside, result.u).reshape(
            (len(ut), len(outside)) + ut.shape[2:])
    if fields is None or not result.success:
        return
    index = geometry.index
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[index]
    t = fields["friction_traction"][index]
    t = lumped * t if t.ndim == 1 else lumped[:, None] * t
    check = verify_contact(problem.K, final, fields["u"], geometry.node_dofs,
                           geometry.normal, geometry.gap,
                           fields["contact_force"][index], stiffness, tol_v,
                           t, lumped * fields["friction_bound"][index],
                           geometry.tangents)
    result.verification = worst_verification([result.verification, check],
                                             tol_v)
    result.verification["excluded"] = verify_excluded(
        problem, geometry, fields["u"], check["length_scale"], tol_v)
    if not check["passed"]:
        result.update(success=False, message=(
            "the last load step fails verification on every node of Γc: "
            + ", ".join(check["failed"])))
