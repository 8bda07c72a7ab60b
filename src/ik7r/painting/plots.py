"""Figures of a painting trajectory: the paper's Figure 12, a 3-D view, an animation.

matplotlib is imported inside the functions (Agg backend), so importing this module is cheap.
Plots are drawn in the robot's world frame (the base frame for the paper robot).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import PathLike
    from ..robot.model import Robot
    from .interpolate import Trajectory

from pathlib import Path as FilePath

import numpy as np

__all__ = ["plot_joint_trajectory", "plot_path_3d", "animate_painting", "plot_gun_speed", "plot_joint_limits",
           "DEFAULT_FRAMES"]

#: Default number of animation frames (the cap of ``ik7r paint --frames``).
DEFAULT_FRAMES = 60
_LABELS = ("θ1", "θ2", "θ3", "θ4", "θ5", "θ7")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_joint_trajectory(trajectory: Trajectory, out: PathLike, robot: Robot | None = None, *,
                          title: str | None = None) -> FilePath:
    """The paper's Figure 12: joint positions, velocities and accelerations against time.

    Parameters
    ----------
    trajectory : Trajectory
        ``t`` (M,) s; ``q``, ``dq``, ``ddq`` (M, 6) in rad, rad/s, rad/s^2.
    out : str or Path
        PNG (or any format matplotlib writes, by suffix).
    robot : Robot, optional
        Names the robot in the title and gives the joint-6 coupling note.
    title : str, optional

    Returns
    -------
    Path
        ``out``.
    """
    plt = _pyplot()
    t = np.asarray(trajectory.t)
    panels = [(trajectory.q, "(a) joint position", "deg"), (trajectory.dq, "(b) joint velocity", "deg/s"),
              (trajectory.ddq, "(c) joint acceleration", "deg/s²")]
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    try:
        for ax, (x, name, unit) in zip(axes, panels):
            for j in range(6):
                ax.plot(t, np.degrees(np.asarray(x)[:, j]), label=_LABELS[j], lw=1.2)
            ax.set_ylabel(f"{name} ({unit})")
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel("time (s)")
        axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.25))
        note = ""
        if robot is not None:
            m, off = robot.coupling
            note = f"robot {robot.name}; θ6 = {m:g} θ5" + (f" + {np.degrees(off):g}°" if off else "")
        if title is None:
            title = "Joint trajectory" + (f" ({note})" if note else "")
        fig.suptitle(title)
        fig.tight_layout()
        fig.savefig(out, dpi=120)
    finally:
        plt.close(fig)
    return FilePath(out)


def _world_path(robot, positions):
    P = np.asarray(positions, dtype=float)
    return P @ robot.base[:3, :3].T + robot.base[:3, 3]


def _skeleton(robot, q) -> np.ndarray:
    """Origins of the base, frames 1..7 and the tool ``(..., 9, 3)`` (world)."""
    return robot.frames(q)[..., :3, 3]


def _equal_axes(ax, pts) -> None:
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    c, r = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo)) * 1.05 + 1e-9
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))


def plot_path_3d(robot: Robot, trajectory: Trajectory, out: PathLike, *, postures: int = 5,
                 title: str | None = None) -> FilePath:
    """A 3-D view of the path (the rows' path points) with ``postures`` robot postures along it.

    The robot is drawn as the polyline through the origins of its frames (base, 1..7, tool).
    """
    plt = _pyplot()
    P = _world_path(robot, trajectory.positions)
    idx = np.unique(np.linspace(0, len(trajectory.t) - 1, max(1, postures)).round().astype(int))
    S = _skeleton(robot, np.asarray(trajectory.q)[idx])
    fig = plt.figure(figsize=(8, 7))
    try:
        ax = fig.add_subplot(projection="3d")
        ax.plot(P[:, 0], P[:, 1], P[:, 2], color="tab:red", lw=1.0, label="path")
        cmap = plt.get_cmap("viridis")
        for k, (i, s) in enumerate(zip(idx, S)):
            col = cmap(k / max(1, len(idx) - 1))
            ax.plot(s[:, 0], s[:, 1], s[:, 2], "-o", color=col, ms=2.5, lw=2,
                    label=f"t = {trajectory.t[i]:.2f} s")
        _equal_axes(ax, np.vstack([P, S.reshape(-1, 3)]))
        u = robot.unit
        ax.set_xlabel(f"x ({u})")
        ax.set_ylabel(f"y ({u})")
        ax.set_zlabel(f"z ({u})")
        ax.legend(fontsize=7, loc="upper left")
        ax.set_title(title or f"Painting path and postures (robot {robot.name})")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return FilePath(out)


def animate_painting(robot: Robot, trajectory: Trajectory, out: PathLike, *, frames: int = DEFAULT_FRAMES,
                     fps: int = 12, dpi: float = 72.0) -> FilePath:
    """An animation of the robot painting: a GIF (``.gif``, Pillow) or a self-contained HTML page
    (``.html``, ``to_jshtml``), with ``frames`` frames evenly spread over the duration."""
    if frames < 2:
        raise ValueError(f"frames must be at least 2; got {frames}")
    out = FilePath(out)
    suffix = out.suffix.lower()
    if suffix not in (".gif", ".html", ".htm"):
        raise ValueError(f"the animation is written as .gif or .html; got {out.name!r}")
    plt = _pyplot()
    from matplotlib import animation

    t = np.asarray(trajectory.t)
    P = _world_path(robot, trajectory.positions)
    pick = np.unique(np.linspace(0, len(t) - 1, frames).round().astype(int))
    S = _skeleton(robot, np.asarray(trajectory.q)[pick])
    fig = plt.figure(figsize=(6, 5.5), dpi=dpi)
    try:
        ax = fig.add_subplot(projection="3d")
        ax.plot(P[:, 0], P[:, 1], P[:, 2], color="0.8", lw=0.8)
        painted, = ax.plot([], [], [], color="tab:red", lw=2.0)
        arm, = ax.plot([], [], [], "-o", color="tab:blue", ms=3, lw=2.5)
        label = ax.set_title("")
        _equal_axes(ax, np.vstack([P, S.reshape(-1, 3)]))
        u = robot.unit
        ax.set_xlabel(f"x ({u})")
        ax.set_ylabel(f"y ({u})")
        ax.set_zlabel(f"z ({u})")

        def draw(k):
            i = pick[k]
            painted.set_data_3d(P[:i + 1, 0], P[:i + 1, 1], P[:i + 1, 2])
            s = S[k]
            arm.set_data_3d(s[:, 0], s[:, 1], s[:, 2])
            label.set_text(f"robot {robot.name}   t = {t[i]:.2f} s")
            return painted, arm, label

        anim = animation.FuncAnimation(fig, draw, frames=len(pick), interval=1000.0 / fps, blit=False)
        if suffix == ".gif":
            anim.save(out, writer=animation.PillowWriter(fps=fps), dpi=dpi)
        else:
            out.write_text("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>ik7r painting, robot "
                           f"{robot.name}</title></head><body>\n{anim.to_jshtml(fps=fps)}\n</body></html>\n")
    finally:
        plt.close(fig)
    return out


def _spray_spans(t, spray):
    """(start, end) times of the runs of spray-on rows."""
    m = np.concatenate([[False], np.asarray(spray, dtype=bool), [False]]).astype(int)
    d = np.diff(m)
    return [(t[a], t[b - 1]) for a, b in zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1))]


def plot_gun_speed(trajectory, out, robot=None, *, title: str | None = None) -> FilePath:
    """The gun's speed against time: actual (forward kinematics of the joints) and commanded,
    spray-on stretches shaded."""
    plt = _pyplot()
    t = np.asarray(trajectory.t)
    unit = robot.unit if robot is not None else "length unit"
    fig, ax = plt.subplots(figsize=(9, 4))
    try:
        for k, (a, b) in enumerate(_spray_spans(t, trajectory.spray)):
            ax.axvspan(a, b, color="tab:green", alpha=0.15, lw=0, label="spray on" if k == 0 else None)
        if trajectory.commanded_speed is not None:
            cmd = np.where(trajectory.spray, trajectory.commanded_speed, np.nan)
            ax.plot(t, cmd, color="0.45", lw=3.5, alpha=0.6, zorder=2, label="commanded")
        ax.plot(t, trajectory.gun_speed, color="tab:blue", lw=1.2, zorder=3,
                label="actual (FK of the joints)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"gun speed ({unit}/s)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
        ax.set_title(title or "Gun speed" + (f" (robot {robot.name})" if robot is not None else ""))
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return FilePath(out)


def plot_joint_limits(trajectory, out, robot, *, title: str | None = None) -> FilePath:
    """Joint speeds and accelerations against time with the robot's limits drawn (dashed, in
    each joint's colour), spray-on stretches shaded."""
    plt = _pyplot()
    t = np.asarray(trajectory.t)
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    try:
        for ax, (x, lim, name, unit) in zip(axes, [(trajectory.dq, robot.velocity, "joint speed", "deg/s"),
                                                    (trajectory.ddq, robot.acceleration, "joint acceleration",
                                                     "deg/s²")]):
            for a, b in _spray_spans(t, trajectory.spray):
                ax.axvspan(a, b, color="tab:green", alpha=0.1, lw=0)
            for j in range(6):
                line, = ax.plot(t, np.degrees(np.asarray(x)[:, j]), lw=1.0, label=_LABELS[j])
                if lim is not None:
                    for sgn in (1, -1):
                        ax.axhline(sgn * np.degrees(lim[j]), color=line.get_color(), ls="--", lw=0.8)
            ax.set_ylabel(f"{name} ({unit})")
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel("time (s)")
        axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.22))
        fig.suptitle(title or f"Joint speeds and accelerations, limits dashed (robot {robot.name})")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return FilePath(out)
