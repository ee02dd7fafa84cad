"""Fig. 16-21: the load increment and the 2-DOF bar (part of
:mod:`solver.output.thesis_figures`)."""

import numpy as np

from .common import LENGTH, FORCE, save_png, pyplot


def load_increment(result, step, path=None, window=3):
    """Fig. 16: the displacement of point A over the load steps of a
    discrete friction run (left) and, zoomed in on ``window`` steps either
    side of ``step`` (1-based κ), the increment Δu_κ from u_{κ−1} to u_κ
    (right)."""
    plt = pyplot()
    u = np.asarray(result.displacement)[:, 0, :]  # point A, (steps, 2)
    fig, (full, zoom) = plt.subplots(1, 2, figsize=(10, 4.2))
    near = slice(max(step - 1 - window, 0), step + window)
    a, b = u[step - 2], u[step - 1]
    for ax in (full, zoom):
        ax.plot(u[:, 0], u[:, 1], ".-", color="0.6", ms=5,
                label=f"u^A after load step κ = 1 … {len(u)}")
        ax.set_xlabel(f"u_x of A [{LENGTH}]")
        ax.set_ylabel(f"u_y of A [{LENGTH}]")
        ax.grid(alpha=0.3)
    lo, hi = u[near].min(axis=0), u[near].max(axis=0)
    pad = 0.15 * max(np.ptp(u[near], axis=0).max(), 1e-12)
    full.add_patch(plt.Rectangle(lo - pad, *(hi - lo + 2 * pad), fill=False,
                                 ec="C3", lw=1.5))
    full.set_title(f"the bar, f_c = {result.friction:g}: path of A",
                   fontsize=10)
    full.legend(fontsize=8, loc="upper right")
    zoom.plot(*a, "o", color="C0", ms=9, label=f"u_κ−1 (κ = {step})")
    zoom.plot(*b, "s", color="C3", ms=9, label="u_κ = u_κ−1 + Δu_κ")
    zoom.annotate("", xy=b, xytext=a,
                  arrowprops=dict(arrowstyle="-|>", color="k", lw=1.5,
                                  shrinkA=6, shrinkB=6))
    zoom.text(*(0.5 * (a + b)), "Δu_κ\n", fontsize=11, ha="center")
    from matplotlib.ticker import MaxNLocator

    zoom.xaxis.set_major_locator(MaxNLocator(4))
    zoom.yaxis.set_major_locator(MaxNLocator(5))
    zoom.set_xlim(lo[0] - pad, hi[0] + pad)
    zoom.set_ylim(lo[1] - pad, hi[1] + pad)
    zoom.legend(fontsize=8, loc="lower left")
    zoom.set_title(f"Fig. 16: one load step, κ = {step} (zoom)", fontsize=10)
    fig.tight_layout()
    return save_png(fig, path)


def bar_sketch(problem, path=None):
    """Fig. 17: the 2-DOF bar system as we reconstruct it: point A held by
    two springs of stiffness K_xx, K_yy, loaded by f, with the rigid
    obstacle at distance s along the normal ν (``two_dof_bar``)."""
    plt = pyplot()
    K = problem.K.toarray()
    f = np.asarray(problem.f)
    s = float(problem.gap[0])
    nu = np.asarray(problem.normal[0])
    fig, ax = plt.subplots(figsize=(6, 5))

    def spring(p, q, n=8, w=0.08):
        p, q = np.asarray(p, float), np.asarray(q, float)
        d = q - p
        L = np.linalg.norm(d)
        e, n_ = d / L, np.array([-d[1], d[0]]) / L
        pts = [p, p + 0.15 * d]
        for i in range(n):
            pts.append(p + (0.15 + 0.7 * (i + 0.5) / n) * d
                       + (w if i % 2 else -w) * n_)
        pts += [p + 0.85 * d, q]
        ax.plot(*np.array(pts).T, "k-", lw=1.2)
        return e

    A = np.array([0.0, 0.0])
    spring([-1.2, 0], A)
    spring([0, 1.2], A)
    for end, horizontal in (([-1.25, 0], False), ([0, 1.25], True)):
        if horizontal:
            ax.plot([-0.2, 0.2], [end[1]] * 2, "k-", lw=2)
            for xi in np.linspace(-0.2, 0.2, 6):
                ax.plot([xi, xi + 0.08], [end[1], end[1] + 0.08], "k-",
                        lw=0.8)
        else:
            ax.plot([end[0]] * 2, [-0.2, 0.2], "k-", lw=2)
            for yi in np.linspace(-0.2, 0.2, 6):
                ax.plot([end[0], end[0] - 0.08], [yi, yi - 0.08], "k-",
                        lw=0.8)
    ax.plot(*A, "ko", ms=9)
    ax.text(0.08, 0.08, "A", fontsize=13)
    ax.text(-0.75, 0.15, f"K_xx = {K[0, 0]:g} {FORCE}/{LENGTH}", fontsize=8,
            ha="center")
    ax.text(0.12, 0.7, f"K_yy = {K[1, 1]:g} {FORCE}/{LENGTH}", fontsize=8)
    fvec = 0.6 * f / np.linalg.norm(f)
    ax.annotate("", xy=A + fvec, xytext=A,
                arrowprops=dict(arrowstyle="-|>", color="C2", lw=2))
    ax.text(*(A + fvec + [0.05, -0.05]),
            f"f = ({f[0]:g}, {f[1]:g}) {FORCE}", color="C2", fontsize=9)
    drawn_gap = 0.9  # s is drawn out of scale
    base = A + drawn_gap * nu
    tangent = np.array([-nu[1], nu[0]])
    line = np.array([base - 1.3 * tangent, base + 1.3 * tangent])
    ax.plot(*line.T, "b-", lw=3)
    for c in np.linspace(-1.2, 1.2, 14):
        p = base + c * tangent
        ax.plot(*np.array([p, p + 0.1 * nu + 0.08 * tangent]).T, "b-",
                lw=0.8)
    ax.annotate("", xy=base - 1.1 * tangent, xytext=A - 1.1 * tangent,
                arrowprops=dict(arrowstyle="<->", color="0.3"))
    ax.text(*(A - 1.0 * tangent + 0.45 * nu), f"s = {s:g} {LENGTH}\n"
            "(not to scale)", fontsize=8, color="0.3")
    ax.text(*(base + 0.9 * tangent + 0.25 * nu), "rigid obstacle",
            color="b", fontsize=9)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_xlim(-1.6, 1.6)
    ax.set_ylim(-1.3, 1.5)
    ax.set_title("Fig. 17: the 2-DOF bar system (our reconstruction of the "
                 "lost figure)", fontsize=10)
    return save_png(fig, path)


#: Quantity name -> (column of the closed form, label, thesis figure).
BAR_QUANTITIES = {
    "contact_force": (2, f"contact force λ [{FORCE}]", 18),
    "friction_force": (3, f"friction force t = D g_t [{FORCE}]", 19),
    "u_x": (0, f"u_x of A [{LENGTH}]", 20),
    "u_y": (1, f"u_y of A [{LENGTH}]", 21),
}


def bar_values(problem, result, quantity):
    lumped = float(np.asarray(problem.M.sum(axis=1)).ravel()[0])
    if quantity == "contact_force":
        return result.contact_force[:, 0]
    if quantity == "friction_force":
        return lumped * result.friction_traction[:, 0]
    return result.displacement[:, 0, 0 if quantity == "u_x" else 1]


def bar_history(problem, results, quantity, references=None, path=None,
                identical_tol=1e-9):
    """One of Fig. 18-21 for the bar: ``quantity`` ("contact_force",
    "friction_force", "u_x", "u_y") per load step, one curve per f_c of
    ``results``, the closed form (``references`` {f_c: (steps, 4) array of
    (u_x, u_y, λ, g_t)}) as a thick grey line under the computed points.
    Curves within ``identical_tol`` of the largest value are drawn once;
    ``fig.max_difference`` holds the difference (None if they differ)."""
    plt = pyplot()
    column, ylabel, number = BAR_QUANTITIES[quantity]
    values = {fc: bar_values(problem, r, quantity) for fc, r in
              results.items()}
    stacked = np.array(list(values.values()))
    spread = float(np.ptp(stacked, axis=0).max())
    same = spread <= identical_tol * max(np.abs(stacked).max(), 1e-300)
    fig, ax = plt.subplots(figsize=(7, 4))
    steps = np.arange(1, stacked.shape[1] + 1)
    if references is not None:
        for i, fc in enumerate(values):
            ax.plot(steps, np.asarray(references[fc])[:len(steps), column],
                    "-", color="0.75", lw=4,
                    label="closed form" if i == 0 else None)
    for i, (fc, v) in enumerate(values.items()):
        if same and i > 0:
            continue
        label = (", ".join(f"f_c = {c:g}" for c in values) +
                 f" (identical: max difference {spread:.1e})" if same
                 else f"f_c = {fc:g}")
        ax.plot(steps, v, ".", color=f"C{i}", ms=5, label=label)
    ax.set_xlabel("load step κ")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Fig. {number}: point A, {len(stacked[0])} load steps",
                 fontsize=10)
    fig.max_difference = spread if same else None
    return save_png(fig, path)
