"""The paper's figures, drawn from the data of :mod:`ik7r.reproduce` (matplotlib, Agg backend).

Each function takes the computed data and a path, writes one PNG and returns the path.
matplotlib is imported inside the functions so that importing this module stays cheap.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["figure6", "figure7", "figure8", "figure9", "figure10"]

#: Errors are drawn on a log scale; exact zeros are drawn at this floor.
FLOOR = 1e-16


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path) -> Path:
    path = Path(path)
    fig.savefig(path, dpi=110)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path


def figure6(curves, path, unit: str = "mm") -> Path:
    """Figure 6: position error against theta5 for the four arm configurations (eq. (11)'s pose).

    Parameters
    ----------
    curves : list of :class:`ik7r.reproduce.wrist.ErrorCurve`
    path : str or Path
    unit : str
        Length unit of the errors.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True, sharey=True)
    for ax, c in zip(axes.ravel(), curves):
        ax.semilogy(np.degrees(c.theta5), np.maximum(c.error, FLOOR), lw=0.8)
        for t in c.solutions_theta5:
            ax.axvline(np.degrees(t), color="tab:red", ls="--", lw=0.8)
        ax.set_title(f"({c.label.lower()}) Configuration {c.label}: Arm = {c.arm}, Elbow = {c.elbow}"
                     f" — {len(c.solutions_theta5)} exact solutions", fontsize=9)
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("theta5 (deg)")
    for ax in axes[:, 0]:
        ax.set_ylabel(f"position error ({unit})")
    axes[0, 0].set_xlim(-180, 180)
    fig.suptitle("Figure 6: position error of one step of the paper's method with theta5 held fixed, "
                 "eq. (11)'s pose\n(dashed: theta5 of the complete solver's exact solutions)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def figure7(count, path) -> Path:
    """Figure 7: number of wrist solutions (and of all solutions) against theta5.

    Parameters
    ----------
    count : :class:`ik7r.reproduce.wrist.WristCount`
    path : str or Path
    """
    plt = _pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    deg = np.degrees(count.theta5)
    rng = np.random.default_rng(0)  # jitter only spreads overlapping markers
    jit = rng.uniform(-1.2, 1.2, len(deg))
    a1.plot(deg + jit, count.wrist_solutions, "o", ms=3, alpha=0.6)
    a1.set_ylabel("solutions of the last\nfour joints (same arm)")
    a1.set_yticks(range(0, int(max(3, count.wrist_solutions.max())) + 1))
    a1.set_title("Figure 7: number of solutions for the last four joints (random q1..q4, q7)", fontsize=10)
    a2.plot(deg + jit, count.all_solutions, "o", ms=3, alpha=0.6, color="tab:green")
    a2.axhline(8, color="tab:red", ls="--", lw=0.8, label="the paper's 'at most eight'")
    a2.set_ylabel("all solutions\nof the pose")
    a2.set_yticks(range(0, int(max(9, count.all_solutions.max())) + 1, 2))
    a2.legend(loc="upper right", fontsize=8)
    a2.set_xlabel("theta5 (deg)")
    a2.set_xlim(-185, 185)
    for ax in (a1, a2):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


def figure8(runs, path, unit: str = "mm") -> Path:
    """Figure 8: position error of the paper's iteration against iterations and against time.

    Parameters
    ----------
    runs : list of :class:`ik7r.reproduce.simulation1.ConvergenceRun`
    path : str or Path
    unit : str
    """
    plt = _pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for r in runs:
        err = np.maximum(r.position_error, FLOOR)
        label = f"start {np.degrees(r.theta5_start):.1f} deg" + ("" if r.ok else " (failed)")
        a1.semilogy(np.arange(1, len(err) + 1), err, "o-", ms=3, lw=1, label=label)
        a2.semilogy(1e3 * r.elapsed, err, "o-", ms=3, lw=1)
    a1.set_xlabel("iteration")
    a1.set_ylabel(f"position error ({unit})")
    a2.set_xlabel("time since the start (ms, this machine)")
    a1.legend(fontsize=7, ncol=2)
    for ax in (a1, a2):
        ax.grid(True, which="major", alpha=0.3)
    fig.suptitle("Figure 8: convergence of the paper's method from random theta5 starts "
                 "(Simulation 1, configuration 1; exact zero drawn at 1e-16)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def figure9(frames, titles, path) -> Path:
    """Figure 9: the postures of Simulation 1's solutions in 3-D.

    Parameters
    ----------
    frames : ndarray, shape (M, 9, 4, 4)
        ``robot.frames(q)`` of each solution (base, frames 1..7, tool).
    titles : list of str, length M
    path : str or Path
    """
    plt = _pyplot()
    m = len(frames)
    cols = 4
    rows = max(1, -(-m // cols))
    fig = plt.figure(figsize=(3.2 * cols, 3.3 * rows))
    pts_all = frames[:, :, :3, 3]
    lo, hi = pts_all.reshape(-1, 3).min(axis=0), pts_all.reshape(-1, 3).max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * float((hi - lo).max()) * 1.05
    for k in range(m):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        p = frames[k, :, :3, 3]
        ax.plot(p[:, 0], p[:, 1], p[:, 2], "-o", color="tab:blue", ms=2.5, lw=2)
        for j in range(1, 8):  # joint axes (z of frames 1..7): tell apart postures sharing link positions
            a = frames[k, j, :3, 2] * 0.12 * half
            o = p[j]
            ax.plot([o[0] - a[0], o[0] + a[0]], [o[1] - a[1], o[1] + a[1]], [o[2] - a[2], o[2] + a[2]],
                    color="0.45", lw=1)
        z = frames[k, -1, :3, 2]
        ax.quiver(p[-1, 0], p[-1, 1], p[-1, 2], z[0], z[1], z[2], length=0.25 * half, color="tab:red")
        ax.plot([p[0, 0]], [p[0, 1]], [p[0, 2]], "ks", ms=5)
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_title(titles[k], fontsize=8)
        ax.tick_params(labelsize=6)
    fig.suptitle("Figure 9: postures of Simulation 1's solutions "
                 "(base square, joint axes grey, tool z axis red)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def figure10(studies, path, unit: str = "mm", published=(0.003, 0.01)) -> Path:
    """Figure 10: position error of every random target for both solvers.

    Parameters
    ----------
    studies : list of :class:`ik7r.reproduce.workspace.WorkspaceStudy`
        The first is the random targets; the singular ones are drawn after them.
    path : str or Path
    unit : str
    published : (float, float)
        The paper's average and maximum errors (drawn as lines).
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(10, 4.8))
    start = 0
    for s in studies:
        idx = np.arange(start, start + len(s.config))
        start += len(s.config)
        single = s.label != "Randomly selected"
        ok = s.paper_ok
        ax.semilogy(idx[ok], np.maximum(s.paper_error[ok], FLOOR), ".", ms=4, color="tab:blue",
                    label=None if single else "the paper's method (ours)")
        if (~ok).any():
            ax.semilogy(idx[~ok], np.maximum(s.paper_error[~ok], FLOOR), "x", ms=6, color="tab:red",
                        label=f"the paper's method failed ({int((~ok).sum())}, last iterate)")
        ax.semilogy(idx[s.complete_ok], np.maximum(s.complete_error[s.complete_ok], FLOOR), ".", ms=3,
                    color="tab:green", alpha=0.6, label=None if single else "complete solver")
        if single:
            ax.axvspan(idx[0] - 0.5, idx[-1] + 0.5, color="0.9", zorder=0)
            ax.text(idx[len(idx) // 2], 1e-1, s.label.replace("Singular configuration", "sing."),
                    ha="center", fontsize=7)
    ax.axhline(published[0], color="k", ls="--", lw=0.8, label=f"paper: average {published[0]} {unit}")
    ax.axhline(published[1], color="k", ls=":", lw=0.8, label=f"paper: maximum {published[1]} {unit}")
    ax.set_xlabel("target (random targets, then the singular ones)")
    ax.set_ylabel(f"position error ({unit})")
    ax.set_ylim(FLOOR / 2, 1e3)
    ax.legend(fontsize=8, loc="center right")
    ax.grid(True, which="major", alpha=0.3)
    ax.set_title("Figure 10: accuracy over the usable workspace (exact zero drawn at 1e-16)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)
