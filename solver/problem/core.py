"""The contact problem object: what the solver sees of one ``.npz`` file."""

import json
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import ProblemError
from ..geometry.cells import cell_name
from ..geometry.curves.parametric import ParametricCurve, check_interval
from ..geometry.curves.polyline import PolylineCurve
from ..geometry.curves.several import SeveralCurves
from ..ncp import stable_norm
from .checks import check_positive_definite
from .format import FORMAT_VERSION
from .surface_spec import surface_spec_text
from .validate import validate_fields

__all__ = ["ContactProblem", "validate_arrays"]


@dataclass(eq=False)
class ContactProblem:
    r"""A contact problem as the solver sees it (one ``.npz`` file): the
    arrays of :data:`~solver.problem.format.KEYS`, K and M as CSR matrices,
    from :func:`load_problem` or built directly (:meth:`validate` checks
    them). ``obstacle``: a 2D curve, a 3D surface (or its spec dict) with
    ``contact_faces``, or None for two bodies (``body``, ``mortar_*``)."""

    K: sp.csr_matrix
    f: np.ndarray
    M: sp.csr_matrix
    contact_dofs: np.ndarray
    meta: dict
    nodes: np.ndarray = None
    cells: np.ndarray = None
    dof_map: np.ndarray = None
    u_prescribed: np.ndarray = None
    contact_nodes: np.ndarray = None
    obstacle: ParametricCurve = None
    gap: np.ndarray = None
    normal: np.ndarray = None
    load_path: np.ndarray = None
    load_path_steps: np.ndarray = None
    load_path_friction: np.ndarray = None
    load_path_prescribed: np.ndarray = None
    contact_faces: np.ndarray = None
    body: np.ndarray = None
    mortar_slave: np.ndarray = None
    mortar_master: np.ndarray = None
    mortar_slave_pair: np.ndarray = None
    mortar_master_pair: np.ndarray = None
    source: str = field(default=None, compare=False)
    _checked: object = field(default=None, init=False, repr=False,
                             compare=False)
    _modes: object = field(default=None, init=False, repr=False,
                           compare=False)
    _held: object = field(default=None, init=False, repr=False,
                          compare=False)

    @property
    def kind(self):
        """``"mesh"`` if the problem carries a mesh, else ``"discrete"``."""
        return "mesh" if self.nodes is not None else "discrete"

    @property
    def dim(self):
        """The space dimension, 2 or 3 (the columns of ``contact_dofs``)."""
        return int(self.contact_dofs.shape[1])

    @property
    def n_bodies(self):
        """B, the number of bodies (1 without a ``body`` key)."""
        return 1 if self.body is None else int(self.body.max()) + 1

    @property
    def is_mortar(self):
        """True for two bodies in contact through mortar segments."""
        return self.mortar_slave is not None

    @property
    def n_dofs(self):
        """Ñ, the number of reduced DOFs."""
        return self.K.shape[0]

    @property
    def n_contact(self):
        """Nc, the number of nodes on Γc."""
        return self.contact_dofs.shape[0]

    def to_arrays(self):
        """The ``.npz`` arrays of this problem, keyed as in :data:`KEYS`."""
        K, M = sp.csr_matrix(self.K), sp.csr_matrix(self.M)
        arrays = {
            "format_version": np.array(FORMAT_VERSION, dtype=np.int64),
            "kind": np.array(self.kind),
            "meta": np.array(json.dumps(self.meta, sort_keys=True)),
            "K_data": K.data, "K_indices": K.indices, "K_indptr": K.indptr,
            "K_shape": np.array(K.shape, dtype=np.int64),
            "f": self.f,
            "M_data": M.data, "M_indices": M.indices, "M_indptr": M.indptr,
            "M_shape": np.array(M.shape, dtype=np.int64),
            "contact_dofs": self.contact_dofs,
        }
        if self.kind == "mesh":
            arrays.update(nodes=self.nodes, cells=self.cells,
                          dof_map=self.dof_map,
                          u_prescribed=self.u_prescribed,
                          contact_nodes=self.contact_nodes)
            if self.dim == 3 and self.is_mortar:
                pass  # the interface is mortar_slave, mortar_master
            elif self.dim == 3:
                arrays["contact_faces"] = self.contact_faces
                arrays["obstacle_surface"] = np.array(
                    surface_spec_text(self.obstacle))
            elif isinstance(self.obstacle, SeveralCurves):
                arrays["obstacle_curves"] = np.array(
                    json.dumps(self.obstacle.spec()))
            elif isinstance(self.obstacle, PolylineCurve):
                arrays["obstacle_points"] = self.obstacle.points
            elif self.obstacle is not None:
                arrays["obstacle_x"] = np.array(self.obstacle.x_text)
                arrays["obstacle_y"] = np.array(self.obstacle.y_text)
                if self.obstacle.t_range is not None:
                    arrays["obstacle_t_range"] = np.array(
                        self.obstacle.t_range, dtype=float)
            search = getattr(self.obstacle, "search_interval", None)
            if search is not None and self.dim == 2:
                arrays["obstacle_search_interval"] = np.array(search,
                                                              dtype=float)
        for name in ("body", "mortar_slave", "mortar_master",
                     "mortar_slave_pair", "mortar_master_pair", "gap",
                     "normal", "load_path", "load_path_steps",
                     "load_path_friction", "load_path_prescribed"):
            if getattr(self, name) is not None:
                arrays[name] = getattr(self, name)
        return arrays

    def validate(self):
        """Check every array; raise :class:`ProblemError` naming the key."""
        validate_fields(self.to_arrays())
        return self

    def set_search_interval(self, t0, t1):
        """Search the obstacle parameter for the gaps in ``[t0, t1]``
        (``--search-interval``; :func:`solver.geometry.curves.
        parameter_window`); ProblemError without an obstacle curve or unless
        t0 < t1 are finite."""
        if self.kind != "mesh":
            raise ProblemError("search interval: a discrete problem has no "
                               "obstacle (its gaps are given)")
        if self.is_mortar:
            raise ProblemError("search interval: a two-body problem has no "
                               "obstacle (it has a master body)")
        if self.dim == 3:
            raise ProblemError("search interval: a 3D obstacle surface has "
                               "no parameter interval t")
        if isinstance(self.obstacle, SeveralCurves):
            raise ProblemError("search interval: several obstacle curves "
                               "have no one parameter t (give each curve "
                               "its search_interval in obstacle_curves)")
        self.obstacle.search_interval = check_interval(
            "search interval", (t0, t1))
        return self

    def __repr__(self):
        """One line: kind, sizes, obstacle and source; never the arrays."""
        parts = [f"kind={self.kind!r}", f"dim={self.dim}",
                 f"dofs={self.n_dofs}", f"contact_nodes={self.n_contact}"]
        if self.kind == "mesh":
            parts += [f"{self._cell_name}={len(self.cells)}",
                      f"nodes={len(self.nodes)}"]
            if self.dim == 3 and not self.is_mortar:
                parts.append(f"contact_faces={len(self.contact_faces)}")
            if self.body is not None:
                parts.append(f"bodies={self.n_bodies}")
            if self.is_mortar:
                facet = "segments" if self.dim == 2 else "triangles"
                parts.append(f"slave_{facet}={len(self.mortar_slave)}, "
                             f"master_{facet}={len(self.mortar_master)}")
            else:
                parts.append(f"obstacle={self._obstacle_text}")
        if self.load_path is not None:
            parts.append(f"load_stages={len(self.load_path)}")
        parts.append(f"source={self.source!r}")
        return f"ContactProblem({', '.join(parts)})"

    @property
    def _cell_name(self):
        name = cell_name(self.dim, np.shape(self.cells)[1]) or "cell"
        return {"hexahedron": "hexahedra", "tetrahedron": "tetrahedra"}.get(
            name, name + "s")

    @property
    def _obstacle_text(self):
        """The obstacle for ``repr``: a surface spec dict by its kind."""
        if isinstance(self.obstacle, dict):
            return f"<surface spec {self.obstacle.get('kind')!r}>"
        return repr(self.obstacle)

    def check_stiffness(self):
        """Check that K is positive definite, or, for a body held by
        contact only, that its kernel is its rigid-body modes (K with r DOFs
        held, :mod:`solver.linalg.kernel`, is positive definite)
        (:func:`~.checks.check_positive_definite`): one sparse factorisation in
        a fill-reducing order, remembered for this K object (replace
        ``problem.K``, do not modify it in place); the condensed solvers get it
        from the factorisation they need anyway."""
        if self._checked is not self.K:
            from ..linalg import dof_ordering
            K = self.K
            if self.floating:  # K_F: K⁺'s factor (two bodies: v = Tu)
                K = self.held_stiffness()[1]
            check_positive_definite(K, "K", dof_ordering(self))
            self._checked = self.K
        return self

    def rigid_modes(self):
        """(R, C): the rigid-body motions that the Dirichlet conditions
        leave free, an orthonormal basis R (Ñ, r) of them in ker K, and
        their coefficients C on the translations and rotations about the
        centroid (:func:`solver.linalg.kernel.rigid_modes`; several bodies:
        each body's about its own centroid, C body by body); r = 0 for
        supported bodies and a discrete problem (a two-body problem's
        nodewise equivalent is given its modes by
        :mod:`solver.contact.two_body`). Remembered for this K object."""
        if self._modes is None or self._modes[0] is not self.K:
            if self.kind != "mesh" or self._pinned():
                modes = (np.zeros((self.n_dofs, 0)),
                         np.zeros((3 if self.dim == 2 else 6, 0)))
            else:
                from ..linalg.kernel import rigid_modes

                groups = None if self.n_bodies == 1 \
                    else self.body[self.dof_map[:, 0]]
                modes = rigid_modes(self.K, self.dof_points(),
                                    self.dof_map[:, 1], groups=groups)
            self._modes = (self.K, modes)
        return self._modes[1]

    def held_by_supports(self):
        """Whether the Dirichlet conditions alone hold every body (no rigid
        motion left free), known without K (:meth:`_pinned`): the
        partitioned converter's test, which streams K."""
        return self._pinned()

    def _pinned(self):
        """Whether every body's Dirichlet DOFs stop all its rigid motions
        (:func:`solver.linalg.kernel.pinned`, on the DOFs of the cells'
        nodes that are not in ``dof_map``): then K has no rigid-body mode,
        known without the product with K and the SVD of
        :func:`~solver.linalg.kernel.rigid_modes`."""
        from ..linalg.kernel import pinned

        if self.cells is None:
            return False
        fixed = np.zeros(self.nodes.shape, bool)
        fixed[np.asarray(self.cells).ravel()] = True
        fixed[self.dof_map[:, 0], self.dof_map[:, 1]] = False
        node, component = np.nonzero(fixed)
        body = np.zeros(len(self.nodes), np.int64) if self.n_bodies == 1 \
            else np.asarray(self.body)
        return all(pinned(self.nodes[node[body[node] == b]],
                          component[body[node] == b])
                   for b in range(self.n_bodies))

    def held_stiffness(self):
        """(F, K_F) of a floating body: r DOFs F off Γc that remove the
        rigid-body modes (:func:`solver.linalg.kernel.fixing_dofs`) and K
        with them held (:func:`solver.linalg.kernel.held_stiffness`),
        positive definite iff ker K is the modes. Remembered for this K."""
        from ..linalg.kernel import held_stiffness

        if self._held is None or self._held[0] is not self.K:
            fixed = self.fixed_dofs()
            self._held = (self.K, (fixed, held_stiffness(self.K, fixed)))
        return self._held[1]

    def fixed_dofs(self):
        """F of :meth:`held_stiffness` alone (an engine that builds K_F
        itself, :meth:`solver.mpi.engine.PetscEngine.held_condensation`,
        needs no copy of K here)."""
        from ..linalg.kernel import fixing_dofs

        R, _ = self.rigid_modes()
        allowed = np.ones(self.n_dofs, bool)
        allowed[self.contact_dofs[self.contact_dofs >= 0]] = False
        return fixing_dofs(R, np.flatnonzero(allowed))[0]

    def dof_points(self):
        """The coordinates of each reduced DOF's node (Ñ, d)."""
        return self.nodes[self.dof_map[:, 0]]

    @property
    def floating(self):
        """Whether K has rigid-body modes (a body held only by contact)."""
        return self.rigid_modes()[0].shape[1] > 0

    def mark_stiffness_checked(self):
        """Record that K (this K object) was found positive definite by a
        factorisation made elsewhere (a condensation's), so that
        :meth:`check_stiffness` does not factorise it again."""
        self._checked = self.K
        return self

    def refusals(self, gap=None):
        """What a solve would refuse (``--info``): one-line reasons, empty if
        it would start (:mod:`solver.problem.refusals`; one factorisation of K,
        remembered, and one gap search in the ``gap`` mode)."""
        from .refusals import refusals

        return refusals(self, gap or "obstacle")

    def n_load_steps(self, steps=None):
        """Number of load steps: of the ``load_path``, else ``steps``
        (default 100)."""
        if self.load_path is not None:
            # Python integers: a sum of huge stages must not wrap around
            return sum(int(k) for k in self.load_path_steps)
        return 100 if steps is None else int(steps)

    def load_steps(self, steps=None):
        """The load path, one entry per load step, as a generator: (load
        vector f_κ, friction multiplier, Dirichlet values or None, stage
        index). Without a ``load_path``: one stage of ``steps`` steps
        (default 100), f_κ = κ/κc·f and the Dirichlet values scaled alike."""
        if self.load_path is None:
            steps = self.n_load_steps(steps)
            for k in range(1, steps + 1):
                yield (k / steps * self.f, 1.0,
                       None if self.u_prescribed is None
                       else k / steps * self.u_prescribed, 0)
            return
        start = np.zeros_like(self.f)
        prescribed_start = None if self.u_prescribed is None \
            else np.zeros_like(self.u_prescribed)
        for stage, (end, n, factor) in enumerate(zip(
                self.load_path, self.load_path_steps,
                self.load_path_friction)):
            if self.load_path_prescribed is not None:
                prescribed_end = self.load_path_prescribed[stage]
            elif self.u_prescribed is not None:
                prescribed_end = self.u_prescribed * (
                    np.linalg.norm(end) / max(np.linalg.norm(self.f), 1e-300))
            else:
                prescribed_end = None
            for k in range(1, int(n) + 1):
                w = k / n
                value = None if prescribed_end is None else \
                    (1 - w) * prescribed_start + w * prescribed_end
                yield ((1 - w) * start + w * end, float(factor), value,
                       stage)
            start, prescribed_start = end, prescribed_end

    def full_displacement(self, u, prescribed=None):
        """Nodal displacements (n_nodes, dim) from a reduced vector ``u``.

        Free DOFs take ``u``, Dirichlet DOFs take ``prescribed`` (default
        ``u_prescribed``, the values of the full load)."""
        if self.kind != "mesh":
            raise ProblemError("full_displacement: a discrete problem has "
                               "no mesh")
        full = (self.u_prescribed if prescribed is None
                else np.asarray(prescribed, float)).copy()
        full[self.dof_map[:, 0], self.dof_map[:, 1]] = u
        return full

    def summary(self, check=False, gap=None):
        """A dict of the problem's main figures (for ``--info``), every
        number finite; with ``check`` also ``"checks"`` (those made) and
        ``"refusals"`` (:meth:`refusals` for the ``gap`` mode)."""
        active = (self.contact_dofs >= 0).all(axis=1)
        info = {
            "kind": self.kind,
            "dim": self.dim,
            "dofs": int(self.n_dofs),
            "contact_nodes": int(self.n_contact),
            "contact_nodes_free": int(active.sum()),
            "K_nnz": int(self.K.nnz),
            # no overflow of the squares: K's entries may reach 1e300
            "K_norm_fro": stable_norm(sp.csr_matrix(self.K).data),
            "K_norm_max": float(abs(self.K).max()),
            "f_norm": stable_norm(self.f),
            "M_sum": float(self.M.sum()),
        }
        if self.kind == "mesh" and self.dim == 3 and not self.is_mortar:
            spec = self.obstacle.spec() if hasattr(self.obstacle, "spec") \
                else self.obstacle
            info.update({"nodes": int(len(self.nodes)),
                         self._cell_name: int(len(self.cells))},
                        contact_faces=int(len(self.contact_faces)),
                        obstacle=spec)
        elif self.is_mortar:
            facet = "segments" if self.dim == 2 else "triangles"
            info.update({"nodes": int(len(self.nodes)),
                         self._cell_name: int(len(self.cells)),
                         "bodies": self.n_bodies,
                         "pairs": int(max(self.mortar_slave_pair.max(),
                                          self.mortar_master_pair.max())) + 1,
                         f"slave_{facet}": int(len(self.mortar_slave)),
                         f"master_{facet}": int(len(self.mortar_master))})
        elif self.kind == "mesh":
            info.update({"nodes": int(len(self.nodes)),
                         self._cell_name: int(len(self.cells))},
                        obstacle=(
                            [self.obstacle.x_text, self.obstacle.y_text]
                            if isinstance(self.obstacle, ParametricCurve)
                            else {"curves": self.obstacle.spec()}
                            if isinstance(self.obstacle, SeveralCurves)
                            else repr(self.obstacle)),
                        obstacle_t_range=self.obstacle.t_range,
                        obstacle_search_interval=getattr(
                            self.obstacle, "search_interval", None))
        else:
            info.update(gap=self.gap.tolist(), normal=self.normal.tolist())
        info["meta"] = self.meta
        if check:
            from .refusals import checks_made

            info.update(checks=checks_made(self, gap or "obstacle"),
                        refusals=self.refusals(gap))
        return info


def validate_arrays(arrays):
    """Validate a dict of ``.npz`` arrays and build a
    :class:`ContactProblem` (ProblemError naming the first key found
    missing, unexpected or malformed)."""
    return ContactProblem(**validate_fields(arrays))
