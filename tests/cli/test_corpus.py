"""The hostile-input corpus (``corpus/``, made by ``make_corpus.py``): every file and argument
list ends with a documented exit status, one or two lines on stderr naming the problem, and
no traceback; the library raises its documented errors, naming the file."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _run import assert_well_behaved, run_cli

import ik7r

CORPUS = Path(__file__).parent / "corpus"


def assert_exit(code, err, status, name, word):
    """The command ended with exit ``status`` and no traceback; when it failed, stderr names the
    file ``name`` and says ``word``."""
    assert_well_behaved(code, err)
    assert code == status, err
    if status:
        assert name in err and word in err, err

# (file, exit status, a word of the message); fk 0 0 0 0 0 0 --robot FILE
ROBOTS = [
    ("axis_1e200.urdf", 0, ""),  # a long axis is a direction like any other
    ("axis_overflow.urdf", 2, "finite"),
    ("axis_zero.urdf", 2, "axis must not be zero"),
    ("base_is_a_number.toml", 2, "[base]: must be a table"),
    ("billion_laughs.urdf", 2, "not valid XML"),
    ("binary.toml", 2, "not UTF-8"),
    ("bool_in_limits.toml", 2, "'lower' must be a list of 6 numbers"),
    ("coupling_is_a_string.toml", 2, "[coupling]: must be a table"),
    ("description_is_a_table.toml", 2, "'description' must be a string"),
    ("dh_is_a_list.toml", 2, "[dh]: must be a table"),
    ("empty.toml", 2, "'name' must be a string"),
    ("external_entity.urdf", 2, "not valid XML"),
    ("huge_integer.toml", 2, "'d' must be finite"),
    ("latin1.toml", 2, "not UTF-8"),
    ("loop.urdf", 2, "loop"),
    ("nan_in_dh.toml", 2, "'d' must be finite"),
    ("nested_arrays.toml", 2, "nested too deeply"),
    ("nested_inline_tables.toml", 2, "nested too deeply"),
    ("not_toml.toml", 2, "not valid TOML"),
    ("not_xml.urdf", 2, "not valid XML"),
    ("short_list.toml", 2, "list of 7 numbers"),
    ("tool_is_a_string.toml", 2, "[tool]: must be a table"),
    ("two_parents.urdf", 2, "child of two joints"),
    ("typo_in_coupling.toml", 2, "unknown keys ['multiplyer']"),
    ("typo_in_dh.toml", 2, "unknown keys ['theta_ofset']"),
    ("typo_in_limits.toml", 2, "unknown keys ['velocty']"),
    ("unknown_encoding.urdf", 2, "not valid XML"),
    ("utf16.toml", 2, "UTF-16"),
    ("utf16_declared_utf8.urdf", 2, "not valid XML"),
    ("with_bom.toml", 0, ""),
    ("wrong_root.urdf", 2, "root element must be <robot>"),
]


@pytest.mark.parametrize("name, status, word", ROBOTS)
def test_robot_files_at_the_command_line(name, status, word):
    path = CORPUS / "robots" / name
    code, out, err = run_cli("fk", "0", "0", "0", "0", "0", "0", "--robot", path)
    assert_exit(code, err, status, name, word)
    if status:
        assert len(err.splitlines()) == 1, err
    else:
        assert err == "" and "position" in out


@pytest.mark.parametrize("name, status, word", ROBOTS)
def test_robot_files_in_the_library_raise_typed_errors(name, status, word):
    path = CORPUS / "robots" / name
    if status == 0:
        robot = ik7r.load_robot(path)
        paper = ik7r.load_robot()
        q = np.random.default_rng(5).uniform(-1, 1, (10, 6))
        if path.suffix == ".toml":
            np.testing.assert_allclose(robot.fk(q), paper.fk(q), atol=1e-9)
        return
    with pytest.raises((ik7r.RobotFileError, ik7r.FamilyError)) as info:
        ik7r.load_robot(path)
    assert str(path) in str(info.value) and word in str(info.value)


def test_load_robot_refuses_what_is_not_a_name_or_a_path():
    for bad in (5, 2.5, None.__class__, ["paper"], b"\x00"):
        with pytest.raises(ValueError, match="robot must be|not a robot"):
            ik7r.load_robot(bad)
    with pytest.raises(FileNotFoundError, match="no such robot file"):
        ik7r.load_robot("/nonexistent/robot.toml")


def test_toml_text_with_a_byte_order_mark_is_the_same_robot():
    text = (Path(ik7r.__file__).parent / "robot" / "data" / "paper.toml").read_text()
    from ik7r.robot.files import robot_from_toml

    a, b = robot_from_toml("\ufeff" + text), robot_from_toml(text)
    np.testing.assert_array_equal(a.dh, b.dh)


def test_robot_file_size_is_limited_and_the_limit_can_be_raised(tmp_path):
    src = (CORPUS / "robots" / "with_bom.toml").read_bytes()
    f = tmp_path / "r.toml"
    f.write_bytes(src + b"\n" + b"#" * 5000 + b"\n")
    with pytest.raises(ik7r.RobotFileError, match=r"max_bytes="):
        ik7r.load_robot(f, max_bytes=4000)
    assert ik7r.load_robot(f, max_bytes=10_000).name == "paper"


# (file, exit status, a word); paint path FILE --no-plots
PATHS = [
    ("with_bom.csv", 0, ""),
    ("crlf.csv", 0, ""),
    ("duplicate_column.csv", 2, "duplicate columns ['x']"),
    ("latin1.csv", 2, "not UTF-8"),
    ("utf16.csv", 2, "UTF-16"),
    ("huge_values.csv", 2, "too large"),
    ("nan_value.csv", 2, "line 13"),
    ("text_value.csv", 2, "line 13"),
    ("ragged.csv", 2, "line 13"),
    ("header_only.csv", 2, "at least 2 rows"),
    ("no_header.csv", 2, "lacks columns"),
    ("nul_bytes.csv", 2, "NUL"),
    ("both_orientations.csv", 2, "not both"),
    ("bad_quaternion.csv", 2, "unit norm"),
    ("unterminated_quote.csv", 2, "line 2"),
]


@pytest.mark.parametrize("name, status, word", PATHS)
def test_path_csv_files(name, status, word, tmp_path):
    path = CORPUS / "csv" / name
    code, out, err = run_cli("paint", "path", path, "--no-plots", "--out", tmp_path / "o")
    assert_exit(code, err, status, name, word)
    if status:
        assert not (tmp_path / "o").exists()  # bad input leaves nothing
    else:
        assert (tmp_path / "o" / "trajectory.csv").is_file() and (tmp_path / "o" / "report.txt").is_file()


def test_a_bom_csv_is_the_same_path_as_without():
    from ik7r.painting import load_path_csv

    a = load_path_csv(CORPUS / "csv" / "with_bom.csv")
    b = load_path_csv(CORPUS / "csv" / "crlf.csv")
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.positions[0].tolist() == [1000.0, -100.0, 300.0]


# (option, file, exit status, a word); batch OPTION FILE --out DIR
ARRAYS = [
    ("--joints", "joints.npz", 0, ""),
    ("--poses", "poses.npz", 0, ""),
    ("--poses", "poses.npy", 0, ""),
    ("--joints", "joints_with_nan_rows.npy", 0, ""),
    ("--poses", "poses_with_nan_row.npy", 0, ""),
    ("--joints", "broken.npz", 2, "not a valid .npz"),
    ("--joints", "two_arrays.npz", 2, "several arrays"),
    ("--joints", "joints_complex.npy", 2, "real numbers"),
    ("--poses", "poses_complex.npy", 2, "real numbers"),
    ("--joints", "joints_header_only.npy", 2, "not a .npy"),
    ("--joints", "joints_truncated.npy", 2, "not a .npy"),
    ("--joints", "joints_object.npy", 2, "not a .npy"),
    ("--joints", "joints_strings.npy", 2, "real numbers"),
    ("--joints", "joints_wrong_shape.npy", 2, "shape (N, 6)"),
    ("--poses", "joints.npz", 2, "shape (N, 4, 4)"),
    ("--joints", "not_an_array.npy", 2, "not a .npy"),
    ("--joints", "missing.npy", 2, "no such file"),
]


@pytest.mark.parametrize("option, name, status, word", ARRAYS)
@pytest.mark.parametrize("out", ["sols", "sols.npz"])
def test_batch_array_files(option, name, status, word, out, tmp_path):
    code, stdout, err = run_cli("batch", option, CORPUS / "arrays" / name, "--out", tmp_path / out)
    assert_exit(code, err, status, name, word)
    if status:
        assert list(tmp_path.iterdir()) == []  # nothing written, nothing hidden
    else:
        assert (tmp_path / out).exists()
        assert [p.name for p in tmp_path.iterdir()] == [out]


def test_batch_marks_nan_joint_rows_and_solves_the_rest(tmp_path):
    from helpers import dh_product

    q = np.load(CORPUS / "arrays" / "joints_with_nan_rows.npy")
    code, out, err = run_cli("batch", "--joints", CORPUS / "arrays" / "joints_with_nan_rows.npy",
                             "--out", tmp_path / "s", "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["invalid"] == 2 and summary["poses"] == 20
    sols = np.load(tmp_path / "s" / "q.npy")
    off = np.load(tmp_path / "s" / "offsets.npy")
    assert off.shape == (21,) and off[0] == 0 and off[-1] == len(sols)
    for i in range(20):
        mine = sols[off[i]:off[i + 1]]
        if i in (3, 7):
            assert len(mine) == 0
            continue
        # every solution reaches the pose of the row (an independent FK), the row's joints among them
        T = dh_product(q[i])
        for s in mine:
            F = dh_product(s)
            assert np.abs(F[:3, 3] - T[:3, 3]).max() < 1e-6 and np.abs(F[:3, :3] - T[:3, :3]).max() < 1e-9
        wrapped = np.angle(np.exp(1j * (mine - q[i])))
        assert np.abs(wrapped).max(axis=1).min() < 1e-6


def test_ik_batch_marks_nan_seed_rows_and_solves_the_rest():
    from helpers import dh_product

    robot = ik7r.load_robot()
    rng = np.random.default_rng(13)
    q = rng.uniform(-1, 1, (50, 6))
    seed = q + 0.01
    seed[[4, 17]] = np.nan
    seed[30, 2] = np.inf
    got, ok = robot.ik_batch(robot.fk(q), config=robot.config_of(q)[0], seed=seed)
    assert not ok[[4, 17, 30]].any() and np.isnan(got[[4, 17, 30]]).all()
    rest = np.setdiff1d(np.arange(50), [4, 17, 30])
    assert ok[rest].sum() >= 1
    for i in rest[ok[rest]]:
        F, T = dh_product(got[i]), dh_product(q[i])
        assert np.abs(F[:3, 3] - T[:3, 3]).max() < 1e-6


@pytest.mark.parametrize("call", [
    lambda r: r.fk(np.zeros(6, complex)),
    lambda r: r.ik_batch(np.eye(4, dtype=complex)[None], 1),
    lambda r: r.ik_all_batch(np.eye(4, dtype=complex)[None]),
    lambda r: r.ik(np.eye(4) + 0j),
    lambda r: r.fk([0, 0, 0, 0, 0, 1j]),
])
def test_complex_input_is_an_error_not_a_real_part(call):
    import warnings

    robot = ik7r.load_robot()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning: a ValueError
        with pytest.raises(ValueError, match="complex"):
            call(robot)
