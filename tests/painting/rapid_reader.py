"""A small reader of the RAPID subset ik7r writes, written for the tests from the RAPID manual's
syntax (not from ik7r's writer): declarations ``CONST jointtarget name := [[a1..a6], [e1..e6]];``
and ``CONST zonedata``, procedures ``PROC name() ... ENDPROC``, and the statements
``MoveAbsJ target, speed [\\T:=time], zone, tool;``, ``SetDO signal, value;`` and procedure
calls ``name;``. ``!`` starts a comment. Execution from ``main`` gives the moves in order, each
with the digital outputs in force while it runs."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_JOINTTARGET = r"CONST\s+jointtarget\s+(\w+)\s*:=\s*\[\[(.*?)\]\s*,\s*\[(.*?)\]\]\s*;"
_MOVEABSJ = (rf"MoveAbsJ\s+(\w+)\s*,\s*(\w+)\s*(?:\\T\s*:=\s*({_NUM}))?\s*,\s*(\w+)\s*,"
             r"\s*(\w+)\s*;")


@dataclass
class Move:
    target: str
    axes: list[float]
    external: list[float]
    speed: str
    time: float | None
    zone: str
    tool: str
    outputs: dict = field(default_factory=dict)


@dataclass
class Module:
    name: str
    jointtargets: dict
    zonedata: dict
    procs: dict


def _strip(line: str) -> str:
    return line.split("!", 1)[0].strip()


def parse(text: str) -> Module:
    lines = [_strip(x) for x in text.splitlines()]
    lines = [x for x in lines if x]
    head = re.fullmatch(r"MODULE\s+(\w+)", lines[0])
    assert head, f"not a module: {lines[0]!r}"
    assert lines[-1] == "ENDMODULE", lines[-1]
    jt, zd, procs = {}, {}, {}
    cur = None
    for line in lines[1:-1]:
        if cur is None:
            if m := re.fullmatch(_JOINTTARGET, line):
                axes = [float(v) for v in m.group(2).split(",")]
                ext = [float(v) for v in m.group(3).split(",")]
                assert len(axes) == 6 and len(ext) == 6, line
                jt[m.group(1)] = (axes, ext)
            elif m := re.fullmatch(r"CONST\s+zonedata\s+(\w+)\s*:=\s*\[(\w+)\s*,(.*)\]\s*;", line):
                zd[m.group(1)] = [m.group(2)] + [float(v) for v in m.group(3).split(",")]
            elif m := re.fullmatch(r"PROC\s+(\w+)\s*\(\s*\)", line):
                cur = m.group(1)
                procs[cur] = []
            else:
                raise AssertionError(f"unexpected declaration {line!r}")
        elif line == "ENDPROC":
            cur = None
        else:
            procs[cur].append(line)
    return Module(head.group(1), jt, zd, procs)


def run(module: Module, proc: str = "main") -> list[Move]:
    """The moves executed from ``proc``, with the outputs set before each."""
    outputs: dict = {}
    moves: list[Move] = []

    def execute(name, depth=0):
        assert depth < 20, "recursion"
        for st in module.procs[name]:
            if m := re.fullmatch(_MOVEABSJ, st):
                target, speed, t, zone, tool = m.groups()
                assert zone == "fine" or re.fullmatch(r"z\d+", zone) or zone in module.zonedata, zone
                axes, ext = module.jointtargets[target]
                moves.append(Move(target, axes, ext, speed, None if t is None else float(t), zone, tool,
                                  dict(outputs)))
            elif m := re.fullmatch(r"SetDO\s+(\w+)\s*,\s*([01])\s*;", st):
                outputs[m.group(1)] = int(m.group(2))
            elif m := re.fullmatch(r"(\w+)\s*;", st):
                execute(m.group(1), depth + 1)
            else:
                raise AssertionError(f"unexpected statement {st!r}")

    execute(proc)
    return moves
