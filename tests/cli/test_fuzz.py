"""Property-based fuzzing of the loaders and the argument parser: whatever comes in, the
library raises its documented errors (naming the file) and the command line answers with a
documented exit status, no traceback and at most two lines on stderr."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
from _run import assert_well_behaved, run_cli
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ik7r
from ik7r.robot.files import robot_from_toml
from ik7r.robot.urdf import robot_from_urdf_string

PAPER_TOML = (Path(ik7r.__file__).parent / "robot" / "data" / "paper.toml").read_text()
PAPER_URDF = ik7r.load_robot().to_urdf()
FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

HOSTILE = ["nan", "inf", "-inf", "1e400", "1e300", "-1e300", "0", "-0", "1e-320", "[]", "{}", "''",
           '"x"', "true", "[[1]]", "[1, 2]", "9" * 60, "[" * 50 + "]" * 50, "{a = {b = 1}}",
           "[0, 0, 0, 0, 0, 0, 0]", "[1e308, 0, 0, 0, 0, 0, 0]", "[nan, 0, 0, 0, 0, 0, 0]",
           '"\u00e9\u0000"', "1979-05-27", "[1, 'a', 3, 4, 5, 6, 7]"]
TOKEN = st.one_of(st.sampled_from(HOSTILE), st.text(max_size=12),
                  st.floats(allow_nan=True, allow_infinity=True).map(repr),
                  st.integers(min_value=-(10 ** 30), max_value=10 ** 30).map(str))


def _typed(call, source: str) -> None:
    try:
        call()
    except (ik7r.RobotFileError, ik7r.FamilyError) as exc:
        assert str(exc).startswith(source) or source in str(exc), str(exc)


@FUZZ
@given(data=st.data())
def test_toml_with_hostile_values(data):
    lines = PAPER_TOML.splitlines()
    for _ in range(data.draw(st.integers(1, 3))):
        i = data.draw(st.integers(0, len(lines) - 1))
        key = lines[i].split("=")[0].strip() if "=" in lines[i] else data.draw(st.sampled_from(
            ["x", "a", "base", "tool", "[base]", "[tool]", "[dh]", "[coupling]", "sign"]))
        lines[i] = f"{key} = {data.draw(TOKEN)}" if not key.startswith("[") else key
    _typed(lambda: robot_from_toml("\n".join(lines), source="fuzz.toml"), "fuzz.toml")


@FUZZ
@given(text=st.text(max_size=300))
def test_toml_arbitrary_text(text):
    _typed(lambda: robot_from_toml(text, source="fuzz.toml"), "fuzz.toml")


@FUZZ
@given(data=st.data())
def test_urdf_with_hostile_attributes(data):
    import re

    text = PAPER_URDF
    attrs = list(re.finditer(r'="([^"]*)"', text))
    for _ in range(data.draw(st.integers(1, 3))):
        m = attrs[data.draw(st.integers(0, len(attrs) - 1))]
        value = data.draw(st.one_of(TOKEN, st.sampled_from(["0 0 1e200", "1e400 0 0", "0 0 0", "a b c",
                                                            "1 2", "nan nan nan", "1e-300 0 0"])))
        value = value.replace('"', "").replace("&", "").replace("<", "")
        text = text[:m.start(1)] + value + text[m.end(1):]
        attrs = list(re.finditer(r'="([^"]*)"', text))
    _typed(lambda: robot_from_urdf_string(text, source="fuzz.urdf"), "fuzz.urdf")


def test_urdf_origins_beyond_float_range_are_refused_quietly():
    """A joint origin whose squared length overflows float64 (1e200 in every coordinate) is
    refused with a FamilyError naming the bound, and no floating-point warning escapes on the
    way (the fuzzing above once saw numpy's overflow warning from the chain's size)."""
    import re
    import warnings

    import pytest

    for m in re.finditer(r'<origin xyz="([^"]*)"', PAPER_URDF):
        text = PAPER_URDF[:m.start(1)] + "1e200 1e200 1e200" + PAPER_URDF[m.end(1):]
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ik7r.FamilyError, match="MAX_COORDINATE"):
                robot_from_urdf_string(text, source="far.urdf")


@FUZZ
@given(data=st.data())
def test_urdf_with_elements_removed_or_cut(data):
    lines = PAPER_URDF.splitlines()
    k = data.draw(st.integers(0, len(lines) - 1))
    n = data.draw(st.integers(1, 4))
    text = "\n".join(lines[:k] + lines[k + n:])
    if data.draw(st.booleans()):
        text = text[: data.draw(st.integers(0, len(text)))]
    _typed(lambda: robot_from_urdf_string(text, source="fuzz.urdf"), "fuzz.urdf")


@FUZZ
@given(raw=st.binary(max_size=400))
def test_robot_files_of_arbitrary_bytes(raw):
    with tempfile.TemporaryDirectory() as tmp:
        for suffix in (".toml", ".urdf"):
            f = Path(tmp) / f"r{suffix}"
            f.write_bytes(raw)
            _typed(lambda f=f: ik7r.load_robot(f), str(f))


CSV_CELL = st.one_of(st.sampled_from(["1", "-2.5", "nan", "inf", "1e308", "", "x", '"', "1e-400", " 3 "]),
                     st.floats(allow_nan=True).map(repr), st.text(max_size=5))


@FUZZ
@given(header=st.lists(st.sampled_from(["x", "y", "z", "qw", "qx", "qy", "qz", "roll", "pitch", "yaw",
                                        "X", " z", "", "t"]), min_size=0, max_size=8),
       rows=st.lists(st.lists(CSV_CELL, max_size=8), max_size=6), bom=st.booleans())
def test_path_csv(header, rows, bom):
    from ik7r.painting import load_path_csv

    text = ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)
    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "p.csv"
        f.write_bytes((b"\xef\xbb\xbf" if bom else b"") + text.encode("utf-8", "surrogatepass"))
        try:
            path = load_path_csv(f)
        except ValueError as exc:
            assert str(f) in str(exc)
        else:
            assert len(path) >= 2 and np.all(np.isfinite(path.positions))


# ---------------------------------------------------------------- the argument parser
NUMBER = st.one_of(st.sampled_from(["0", "1", "-30", "60", "1e308", "-1e308", "nan", "inf", "1e-320",
                                    "x", "", "--", "-", "0x10", "1_000", "1e400", "90"]),
                   st.floats(allow_nan=True, allow_infinity=True).map(repr))
OPTION = st.sampled_from(["--all", "--json", "--config", "--seed", "--position", "--rpy", "--matrix",
                          "--within-limits", "--robot", "--format", "--unit", "--help", "-h", "--bogus"])
ROBOT = st.sampled_from(["paper", "irb5400", "nope", "/nonexistent.urdf", "", "x.toml"])


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(command=st.sampled_from(["fk", "ik", "export", "", "nonsense", "paint", "batch"]),
       words=st.lists(st.one_of(NUMBER, OPTION, ROBOT), max_size=14))
def test_argument_parser(command, words):
    argv = ([command] if command else []) + words
    if command == "export":
        argv = [w for w in argv if w != "--out"]  # to stdout only
    if command in ("paint", "batch"):  # the parser and the early checks only: no work, no files
        argv = [command, "--bogus-option-stops-here"] + words
    code, out, err = run_cli(*argv)
    assert_well_behaved(code, err)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(option=st.sampled_from(["--spacing", "--step", "--rate", "--duration", "--margin", "--standoff",
                               "--frames", "--postures", "--ramp", "--tolerance", "--config"]),
       value=NUMBER)
def test_paint_options(option, value):
    with tempfile.TemporaryDirectory() as tmp:
        code, out, err = run_cli("paint", "raster", option, value, "--no-plots", "--size", "100", "100",
                                 "--spacing", "50", "--out", Path(tmp) / "o")
        assert_well_behaved(code, err)
        leftovers = [p.name for p in Path(tmp).rglob("*") if p.name.startswith(".")]
        assert leftovers == []
        if code != 0:
            assert not (Path(tmp) / "o" / "report.txt").exists() or code == 1


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random=st.one_of(st.integers(-5, 300).map(str), NUMBER), chunk=st.one_of(st.integers(-1, 500).map(str),
                                                                              NUMBER),
       seed=st.one_of(st.integers(-(10 ** 30), 10 ** 30).map(str), NUMBER))
def test_batch_options(random, chunk, seed):
    with tempfile.TemporaryDirectory() as tmp:
        code, out, err = run_cli("batch", "--random", random, "--chunk", chunk, "--seed", seed,
                                 "--out", Path(tmp) / "s")
        assert_well_behaved(code, err)
        names = sorted(p.name for p in Path(tmp).rglob("*"))
        assert names == (["joints.npy", "meta.json", "offsets.npy", "q.npy", "s"] if code == 0 else [])
