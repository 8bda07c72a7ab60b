"""Typed, readable reports of what happens along a painting path.

Every event is a frozen dataclass with a ``message()`` (also its ``str``) and a class attribute
``blocking``: a blocking event (an unreachable sample, a jump of the joints between samples)
means no continuous joint trajectory follows the path, so :func:`ik7r.painting.paint_path`
raises :class:`PathNotFeasible` instead of returning a trajectory. The others are warnings
that come with the trajectory (a crossing of theta5 = 0 on a continuous branch, a speed limit
exceeded, ...). Angles are stored in rad and printed in degrees; joint indices are 0..5 for
``[q1, q2, q3, q4, q5, q7]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from ..errors import UnreachableError
from ..robot.model import JOINT_LABELS

__all__ = [
    "JOINT_LABELS",
    "PathEvent",
    "Unreachable",
    "BranchChange",
    "WristCrossing",
    "ConfigChange",
    "JointLimit",
    "NearSingularity",
    "SpeedLimit",
    "AccelerationLimit",
    "TimeScaled",
    "DeviationExceeded",
    "CornerStop",
    "CommandedSpeedTooHigh",
    "SlowDown",
    "RampOnPart",
    "PathNotFeasible",
    "format_report",
]


def _deg(x: float) -> str:
    return f"{math.degrees(x):.3f} deg"


def _at(position, unit: str) -> str:
    if position is None:
        return ""
    return f" at ({', '.join(f'{v:.3f}' for v in position)}) {unit}"


def _samples(first: int, last: int) -> str:
    return f"sample {first}" if first == last else f"samples {first}-{last} ({last - first + 1} samples)"


@dataclass(frozen=True)
class PathEvent:
    """Base class of the events; ``str(event)`` is its one-line message."""

    blocking: ClassVar[bool] = False
    kind: ClassVar[str] = "event"

    def message(self) -> str:  # pragma: no cover - every subclass overrides
        return self.kind

    def __str__(self) -> str:
        return self.message()


@dataclass(frozen=True)
class Unreachable(PathEvent):
    """Samples ``first..last`` (path indices, inclusive) have no usable solution, and why."""

    first: int
    last: int
    reason: str
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    blocking: ClassVar[bool] = True
    kind: ClassVar[str] = "unreachable"

    def message(self) -> str:
        return f"unreachable: {_samples(self.first, self.last)}{_at(self.position, self.unit)}: {self.reason}"


@dataclass(frozen=True)
class BranchChange(PathEvent):
    """Between samples ``index - 1`` and ``index`` the joints jump to another solution branch
    (``jump`` rad in joint ``joint``): the robot cannot follow the path continuously there."""

    index: int
    joint: int
    jump: float
    reason: str
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    blocking: ClassVar[bool] = True
    kind: ClassVar[str] = "branch change"

    def message(self) -> str:
        return (f"branch change between samples {self.index - 1} and {self.index}"
                f"{_at(self.position, self.unit)}: {JOINT_LABELS[self.joint]} jumps by "
                f"{_deg(self.jump)}; {self.reason}")


@dataclass(frozen=True)
class WristCrossing(PathEvent):
    """The continuous solution crosses theta5 = ``angle`` (0: straight wrist; pi: fully bent)
    between samples ``index - 1`` and ``index``: the Wrist indicator flips, so the
    configuration changes from ``config_before`` to ``config_after``."""

    index: int
    angle: float
    q5_before: float
    q5_after: float
    config_before: int
    config_after: int
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    kind: ClassVar[str] = "wrist crossing"

    def message(self) -> str:
        where = "0 (straight wrist, a singularity)" if self.angle == 0 else "180 deg (fully bent wrist)"
        return (f"theta5 crosses {where} between samples {self.index - 1} and {self.index}"
                f"{_at(self.position, self.unit)}: q5 goes from {_deg(self.q5_before)} to "
                f"{_deg(self.q5_after)}, configuration {self.config_before} -> {self.config_after}")


@dataclass(frozen=True)
class ConfigChange(PathEvent):
    """The continuous solution changes configuration (Arm or Elbow indicator) between samples
    ``index - 1`` and ``index``."""

    index: int
    config_before: int
    config_after: int
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    kind: ClassVar[str] = "configuration change"

    def message(self) -> str:
        return (f"configuration {self.config_before} -> {self.config_after} between samples "
                f"{self.index - 1} and {self.index}{_at(self.position, self.unit)} (continuous motion)")


@dataclass(frozen=True)
class JointLimit(PathEvent):
    """Joint ``joint`` would pass its limit ``limit`` (reaching ``value``, rad): on the path near
    sample ``index`` (the continuous solution leaves the joint range), or in the interpolated
    trajectory at time ``time`` (s)."""

    joint: int
    value: float
    limit: float
    index: int | None = None
    time: float | None = None
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    kind: ClassVar[str] = "joint limit"

    def message(self) -> str:
        side = "upper" if self.value > self.limit else "lower"
        name = JOINT_LABELS[self.joint]
        if self.index is not None:
            return (f"joint limit: near sample {self.index}{_at(self.position, self.unit)} the continuous "
                    f"solution reaches the {side} limit of {name}, {_deg(self.limit)}")
        return (f"joint limit: the interpolated {name} passes its {side} limit {_deg(self.limit)} at "
                f"t = {self.time:.4f} s (reaching {_deg(self.value)})")


@dataclass(frozen=True)
class NearSingularity(PathEvent):
    """Samples ``first..last`` have theta5 within ``margin`` of 0 or 180 deg (a wrist
    singularity: q4 and q7 turn fast); ``closest`` is the smallest distance, ``q4_turn`` and
    ``q7_turn`` how far q4 and q7 turn from ``first`` to ``last`` (rad)."""

    first: int
    last: int
    closest: float
    margin: float
    q4_turn: float = 0.0
    q7_turn: float = 0.0
    kind: ClassVar[str] = "near singularity"

    def message(self) -> str:
        flip = " (a wrist flip)" if max(self.q4_turn, self.q7_turn) > math.pi / 2 else ""
        return (f"near a wrist singularity: {_samples(self.first, self.last)} have theta5 within "
                f"{_deg(self.margin)} of 0 or 180 deg (closest {_deg(self.closest)}); q4 turns by "
                f"{_deg(self.q4_turn)} and q7 by {_deg(self.q7_turn)} across them{flip}")


@dataclass(frozen=True)
class _JointLimitExceeded(PathEvent):
    """The interpolated speed or acceleration of joint ``joint`` reaches ``peak`` at ``time``
    (s), above its limit ``limit`` (rad/s or rad/s^2, per subclass)."""

    joint: int
    peak: float
    limit: float
    time: float
    rate_unit: ClassVar[str] = ""

    def message(self) -> str:
        u = self.rate_unit
        return (f"{self.kind}: {JOINT_LABELS[self.joint]} reaches {math.degrees(self.peak):.3f} {u} at "
                f"t = {self.time:.4f} s, {self.peak / self.limit:.2f} x its limit "
                f"{math.degrees(self.limit):.3f} {u}")


@dataclass(frozen=True)
class SpeedLimit(_JointLimitExceeded):
    """The interpolated speed of joint ``joint`` reaches ``peak`` (rad/s) at ``time`` (s),
    above its limit ``limit``."""

    kind: ClassVar[str] = "speed limit"
    rate_unit: ClassVar[str] = "deg/s"


@dataclass(frozen=True)
class AccelerationLimit(_JointLimitExceeded):
    """The interpolated acceleration of joint ``joint`` reaches ``peak`` (rad/s^2) at ``time``,
    above its limit ``limit``."""

    kind: ClassVar[str] = "acceleration limit"
    rate_unit: ClassVar[str] = "deg/s^2"


@dataclass(frozen=True)
class TimeScaled(PathEvent):
    """The duration was stretched from ``before`` to ``after`` (s) to respect the joint speed
    and acceleration limits."""

    before: float
    after: float
    kind: ClassVar[str] = "time scaled"

    def message(self) -> str:
        return (f"time scaled: duration {self.before:.4f} s -> {self.after:.4f} s "
                f"(x {self.after / self.before:.4f}) to respect the joint speed and acceleration limits")


@dataclass(frozen=True)
class DeviationExceeded(PathEvent):
    """The interpolated trajectory leaves the path by ``deviation`` (length unit) at ``time``,
    more than ``tolerance`` (densification did not bring it down)."""

    deviation: float
    tolerance: float
    time: float
    unit: str = "mm"
    kind: ClassVar[str] = "deviation"

    def message(self) -> str:
        return (f"deviation: the interpolated tool is {self.deviation:.4g} {self.unit} from the path at "
                f"t = {self.time:.4f} s (tolerance {self.tolerance:g} {self.unit}); a corner in the path? "
                f"round it or sample it more densely")


def _where(u0: float, u1: float, position, unit: str) -> str:
    return f"u = {u0:.1f}-{u1:.1f} {unit}{_at(position, unit)}"


@dataclass(frozen=True)
class CornerStop(PathEvent):
    """The path turns by ``angle`` (rad) at sample ``index`` (a sharp corner of a sampled path):
    the robot stops there (no zone was given to blend it). ``sprayed``: the gun is on there,
    so paint builds up at the corner."""

    index: int
    angle: float
    sprayed: bool = False
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    kind: ClassVar[str] = "corner stop"

    def message(self) -> str:
        tail = " with the gun on (paint builds up there; blend it with a zone)" if self.sprayed else ""
        return (f"corner stop: the path turns by {_deg(self.angle)} at sample {self.index}"
                f"{_at(self.position, self.unit)}; the robot stops there{tail}")


@dataclass(frozen=True)
class CommandedSpeedTooHigh(PathEvent):
    """At the commanded gun speed ``speed`` the joint ``joint`` would exceed its ``quantity``
    limit (``"speed"`` or ``"acceleration"``) by ``ratio`` on the spray-on stretch
    ``u0..u1`` (path parameter); ``feasible`` is the highest gun speed that keeps it within
    the limit there. Blocking unless the stroke may be slowed (``slow_down=True``)."""

    joint: int
    quantity: str
    ratio: float
    u0: float
    u1: float
    speed: float
    feasible: float
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    blocking: ClassVar[bool] = True
    kind: ClassVar[str] = "commanded speed too high"

    def message(self) -> str:
        return (f"commanded speed too high: at {self.speed:g} {self.unit}/s {JOINT_LABELS[self.joint]} "
                f"needs {self.ratio:.2f} x its {self.quantity} limit on "
                f"{_where(self.u0, self.u1, self.position, self.unit)} (spray on); at most "
                f"{self.feasible:.1f} {self.unit}/s there (give slow_down / --slow-down "
                f"to slow the stroke there)")


@dataclass(frozen=True)
class SlowDown(PathEvent):
    """The gun moves slower than commanded on the spray-on stretch ``u0..u1`` (down to
    ``lowest``, length unit per s) to keep joint ``joint`` within its limits; the film there
    is thicker by up to ``speed / lowest``."""

    joint: int
    u0: float
    u1: float
    speed: float
    lowest: float
    position: tuple[float, float, float] | None = None
    unit: str = "mm"
    kind: ClassVar[str] = "slow down"

    def message(self) -> str:
        return (f"slow down: the stroke is slowed on {_where(self.u0, self.u1, self.position, self.unit)} "
                f"(spray on) to {self.lowest:.1f} {self.unit}/s instead of {self.speed:g} (limited by "
                f"{JOINT_LABELS[self.joint]}); the film there is up to {self.speed / self.lowest:.2f} x "
                f"thicker")


@dataclass(frozen=True)
class RampOnPart(PathEvent):
    """``count`` speed ramps of the spray-on passes reach ``depth`` (length unit) onto the part,
    beyond the overspray ``margin``: the gun is slower than commanded there."""

    count: int
    depth: float
    margin: float
    unit: str = "mm"
    kind: ClassVar[str] = "ramp on the part"

    def message(self) -> str:
        return (f"ramp on the part: {self.count} speed ramp{'s' if self.count != 1 else ''} reach up to "
                f"{self.depth:.1f} {self.unit} onto the part (overspray margin {self.margin:g} {self.unit}); "
                f"the gun is below the commanded speed there: give a margin of at least "
                f"{math.ceil(self.margin + self.depth)} {self.unit}")


def format_report(events) -> str:
    """The events, one per line (blocking ones marked ``ERROR``), or ``'no events'``."""
    if not events:
        return "no events"
    return "\n".join(f"{'ERROR' if e.blocking else 'warning'}: {e.message()}" for e in events)


class PathNotFeasible(UnreachableError):
    """No continuous joint trajectory follows the path: some samples are unreachable or the
    joints jump between samples. ``events`` lists what happened and ``solution`` holds the
    :class:`~ik7r.painting.trajectory.PathSolution` (with NaN rows at unreachable samples)."""

    def __init__(self, events, solution=None):
        self.events = list(events)
        self.solution = solution
        blocking = [e for e in self.events if e.blocking]
        head = (f"no continuous joint trajectory follows the path ({len(blocking)} problem"
                f"{'s' if len(blocking) != 1 else ''}):")
        super().__init__(head + "\n" + format_report(self.events))
