"""Fig. 1-3 sketches: the NCP functions and the boundary conditions (part of
:mod:`solver.output.thesis_figures`)."""

import numpy as np

from .common import save_png, pyplot


def ncp_functions(path=None):
    """Fig. 1: a function of one variable with a kink and its
    subderivatives; beside it, the zero sets of φ_min (19) and φ_FB (20)
    (both are the complementarity corner a ≥ 0, b ≥ 0, ab = 0)."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    x = np.linspace(-0.5, 2.5, 301)
    g = np.minimum(x, 2 - x)  # φ_min(x, 2 − x): kink at x = 1
    left.plot(x, g, "b-", lw=2.5, label="g(x) = min(x, 2 − x)")
    xs = np.linspace(0.3, 1.7, 2)
    for slope in np.linspace(-1, 1, 9):
        left.plot(xs, 1 + slope * (xs - 1), "r-", lw=0.8, alpha=0.7)
    left.plot([], [], "r-", lw=0.8,
              label="slopes in ∂g(1) = [−1, 1] (Clarke)\n"
                    "∂_B g(1) = {−1, 1} (its end points)")
    left.annotate("non-smooth point", xy=(1, 1), xytext=(1.75, 1.55),
                  arrowprops=dict(arrowstyle="->"))
    left.set_ylim(-0.6, 1.8)
    left.set_xlabel("x")
    left.set_ylabel("g(x)")
    left.set_title("Fig. 1: a kink and its subdifferential", fontsize=10)
    left.legend(fontsize=8, loc="lower center")

    a, b = np.meshgrid(np.linspace(-1, 2, 301), np.linspace(-1, 2, 301))
    phi_min = np.minimum(a, b)
    phi_fb = np.hypot(a, b) - (a + b)
    right.contour(a, b, phi_min, levels=[-0.5, 0.5], colors="C0",
                  linestyles="--", linewidths=0.8)
    right.contour(a, b, phi_fb, levels=[-0.5, 0.5], colors="C1",
                  linestyles=":", linewidths=1.0)
    right.plot([0, 0, 2], [2, 0, 0], "k-", lw=3,
               label="φ(a, b) = 0 for both: a, b ≥ 0, ab = 0")
    right.plot([], [], "C0--", lw=0.8, label="φ_min = ±0.5")
    right.plot([], [], "C1:", lw=1.0, label="φ_FB = ±0.5")
    right.set_aspect("equal")
    right.set_xlabel("a")
    right.set_ylabel("b")
    right.set_title("NCP functions (19), (20): same zero set", fontsize=10)
    right.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15))
    fig.tight_layout()
    return save_png(fig, path)


def boundary_conditions_sketch(path=None):
    """Fig. 2: a body Ω with ∂Ω_u (supported), ∂Ω_σ (loaded), Γc and the
    rigid obstacle Γo, the gap s and the frame (γ, ν) at a point of Γc."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    t = np.linspace(0, 2 * np.pi, 400)
    body = np.c_[1.6 * np.cos(t), 1.0 * np.sin(t) + 1.2]
    ax.fill(body[:, 0], body[:, 1], color="0.9", ec="k")
    ax.text(-0.3, 1.3, "Ω", fontsize=18)
    # Γc: the lower arc; obstacle below it
    arc = (t > 1.2 * np.pi) & (t < 1.8 * np.pi)
    ax.plot(body[arc, 0], body[arc, 1], "r-", lw=3)
    ax.text(0.55, 0.05, "Γc", color="r", fontsize=13)
    xo = np.linspace(-1.8, 1.8, 100)
    ax.plot(xo, -0.12 + 0.05 * xo ** 2, "b-", lw=2.5)
    ax.text(1.45, -0.15, "Γo", color="b", fontsize=13)
    ax.annotate("", xy=(0, -0.12), xytext=(0, 0.2),
                arrowprops=dict(arrowstyle="<->", color="0.3"))
    ax.text(0.05, 0.0, "s", fontsize=12, color="0.3")
    B = np.array([-0.75, 1.2 - np.sqrt(1 - (0.75 / 1.6) ** 2)])
    nu = np.array([B[0] / 1.6 ** 2, B[1] - 1.2])
    nu /= np.linalg.norm(nu)
    gamma = np.array([-nu[1], nu[0]])
    for vec, name in ((nu, "ν"), (gamma, "γ")):
        ax.annotate("", xy=B + 0.45 * vec, xytext=B,
                    arrowprops=dict(arrowstyle="-|>", color="k"))
        ax.text(*(B + 0.55 * vec - [0.05, 0.05]), name, fontsize=12)
    # ∂Ω_u: left part of the boundary, clamped
    left = (t > 0.8 * np.pi) & (t < 1.15 * np.pi)
    ax.plot(body[left, 0], body[left, 1], "k-", lw=4)
    for xi, yi in body[left][::12]:
        ax.plot([xi, xi - 0.15], [yi, yi - 0.1], "k-", lw=0.8)
    ax.text(-2.3, 1.5, "∂Ω_u\n(u = 0)", fontsize=10)
    # ∂Ω_σ: loaded upper boundary
    for s in np.linspace(0.3 * np.pi, 0.7 * np.pi, 5):
        x, y = 1.6 * np.cos(s), np.sin(s) + 1.2
        ax.annotate("", xy=(x, y), xytext=(x, y + 0.45),
                    arrowprops=dict(arrowstyle="->", color="C2"))
    ax.text(1.0, 2.45, "∂Ω_σ (given traction)", color="C2", fontsize=10)
    ax.set_xlim(-2.5, 2.5)
    ax.set_ylim(-0.5, 2.9)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("Fig. 2: boundary conditions of the contact problem",
                 fontsize=10)
    return save_png(fig, path)
