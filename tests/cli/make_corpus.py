"""Regenerate the hostile-input corpus in ``corpus/`` (run from anywhere; files are committed).

    python tests/cli/make_corpus.py

Each file is small (at most a few kB) and named after what is wrong with it; ``cases.json``
says how ``ik7r`` must answer each (exit status, a word its one-line message must contain).
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
C = HERE / "corpus"

PAPER = (Path(__file__).resolve().parents[2] / "src/ik7r/robot/data/paper.toml").read_text()


def toml(name: str, text: str) -> None:
    (C / "robots" / name).write_text(text, encoding="utf-8")


def raw(sub: str, name: str, data: bytes) -> None:
    (C / sub / name).write_bytes(data)


def main() -> None:
    for sub in ("robots", "csv", "arrays"):
        (C / sub).mkdir(parents=True, exist_ok=True)
    # ---------------------------------------------------------------- TOML robot files
    toml("base_is_a_number.toml", "base = 3\n" + PAPER)  # top-level keys go before the tables
    toml("tool_is_a_string.toml", 'tool = "flange"\n' + PAPER)
    no_dh = PAPER[:PAPER.index("[dh]")] + PAPER[PAPER.index("[coupling]"):]
    toml("dh_is_a_list.toml", "dh = [1, 2]\n" + no_dh)
    toml("typo_in_dh.toml", PAPER.replace("theta_offset", "theta_ofset"))
    toml("typo_in_limits.toml", PAPER.replace("velocity", "velocty"))
    toml("typo_in_coupling.toml", PAPER.replace("multiplier = -1.0", "multiplyer = -1.0"))
    toml("coupling_is_a_string.toml", 'coupling = "mirror"\n'
         + PAPER.replace("[coupling]\nmultiplier = -1.0\noffset = 0.0\n", ""))
    toml("nested_arrays.toml", "description = " + "[" * 2000 + "]" * 2000 + "\n" + PAPER)
    toml("nested_inline_tables.toml", "x = " + "{a = " * 1500 + "1" + "}" * 1500 + "\n" + PAPER)
    toml("huge_integer.toml", PAPER.replace("d = [0, 0, 0, 900", "d = [" + "9" * 400 + ", 0, 0, 900"))
    toml("short_list.toml", PAPER.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, 1000]"))
    toml("nan_in_dh.toml", PAPER.replace("d = [0, 0, 0, 900", "d = [nan, 0, 0, 900"))
    toml("bool_in_limits.toml", PAPER.replace("lower = [-70", "lower = [true"))
    toml("description_is_a_table.toml", PAPER.replace('description = "', 'note = "').replace("note", "#", 0)
         .replace('note = "', '# note = "') + "[description]\nx = 1\n")
    toml("not_toml.toml", "this is = not [ toml\n")
    toml("empty.toml", "")
    raw("robots", "with_bom.toml", b"\xef\xbb\xbf" + PAPER.encode())
    raw("robots", "latin1.toml", PAPER.replace("(Table 1)", "(Tabl\u00e9 1)").encode("latin-1"))
    raw("robots", "utf16.toml", PAPER.encode("utf-16"))
    raw("robots", "binary.toml", bytes(range(256)) * 4)
    # ---------------------------------------------------------------- URDF robot files
    import ik7r

    urdf = ik7r.load_robot().to_urdf()
    i = urdf.index('<axis xyz="0 0 1"/>')
    (C / "robots" / "axis_1e200.urdf").write_text(urdf[:i] + '<axis xyz="0 0 1e200"/>'
                                                 + urdf[i + len('<axis xyz="0 0 1"/>'):])
    (C / "robots" / "axis_overflow.urdf").write_text(urdf[:i] + '<axis xyz="1e400 0 0"/>'
                                                    + urdf[i + len('<axis xyz="0 0 1"/>'):])
    (C / "robots" / "axis_zero.urdf").write_text(urdf[:i] + '<axis xyz="0 0 0"/>'
                                                + urdf[i + len('<axis xyz="0 0 1"/>'):])
    (C / "robots" / "not_xml.urdf").write_text("<robot name='x'><link name='a'>\n")
    (C / "robots" / "billion_laughs.urdf").write_text(
        '<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaaaaaaaa">'
        + "".join(f'<!ENTITY {chr(98 + k)} "{("&" + chr(97 + k) + ";") * 10}">' for k in range(8))
        + ']>\n<robot name="&i;"><link name="a"/></robot>\n')
    (C / "robots" / "external_entity.urdf").write_text(
        '<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY e SYSTEM "file:///etc/passwd">]>\n'
        '<robot name="&e;"><link name="a"/></robot>\n')
    (C / "robots" / "loop.urdf").write_text(
        '<robot name="r"><link name="root"/><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j0" type="fixed"><parent link="root"/><child link="a"/></joint>'
        '<joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>'
        '<joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>\n')
    (C / "robots" / "two_parents.urdf").write_text(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="fixed"><parent link="a"/><child link="c"/></joint>'
        '<joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint></robot>\n')
    (C / "robots" / "wrong_root.urdf").write_text('<model name="r"><link name="a"/></model>\n')
    raw("robots", "utf16_declared_utf8.urdf",
        '<?xml version="1.0" encoding="utf-8"?>\n<robot name="r"/>\n'.encode("utf-16-le"))
    raw("robots", "unknown_encoding.urdf", b'<?xml version="1.0" encoding="klingon"?>\n<robot name="r"/>\n')
    # ---------------------------------------------------------------- CSV paths
    rows = "".join(f"{1000 + 20 * k},{-100 + 10 * k},300\n" for k in range(11))
    raw("csv", "with_bom.csv", b"\xef\xbb\xbf" + ("x,y,z\n" + rows).encode())
    raw("csv", "crlf.csv", ("x,y,z\r\n" + rows.replace("\n", "\r\n")).encode())
    raw("csv", "duplicate_column.csv", ("x,y,z,x\n" + rows.replace(",300\n", ",300,5\n")).encode())
    raw("csv", "latin1.csv", ("# pi\u00e8ce\nx,y,z\n" + rows).encode("latin-1"))
    raw("csv", "utf16.csv", ("x,y,z\n" + rows).encode("utf-16"))
    raw("csv", "huge_values.csv", ("x,y,z\n" + "1e308,1e308,1e308\n-1e308,1e308,-1e308\n"
                                    + "1e308,-1e308,1e308\n").encode())
    raw("csv", "nan_value.csv", ("x,y,z\n" + rows + "nan,0,0\n").encode())
    raw("csv", "text_value.csv", ("x,y,z\n" + rows + "one,two,three\n").encode())
    raw("csv", "ragged.csv", ("x,y,z\n" + rows + "1,2\n").encode())
    raw("csv", "header_only.csv", b"x,y,z\n")
    raw("csv", "no_header.csv", rows.encode())
    raw("csv", "nul_bytes.csv", b"x,y,z\n1,2,3\x00\n4,5,6\n")
    raw("csv", "both_orientations.csv", ("x,y,z,qw,qx,qy,qz,roll,pitch,yaw\n"
                                          + "1,2,3,1,0,0,0,0,0,0\n" * 3).encode())
    raw("csv", "bad_quaternion.csv", ("x,y,z,qw,qx,qy,qz\n" + "1000,0,300,2,0,0,0\n1010,0,300,2,0,0,0\n"
                                       ).encode())
    raw("csv", "unterminated_quote.csv", b'x,y,z\n"1,2,3\n4,5,6\n')
    # ---------------------------------------------------------------- arrays
    robot = ik7r.load_robot()
    rng = np.random.default_rng(13)
    q = rng.uniform(-1, 1, (20, 6))
    T = robot.fk(q)
    np.save(C / "arrays" / "poses.npy", T)
    np.savez(C / "arrays" / "poses.npz", T=T)
    np.savez(C / "arrays" / "joints.npz", q=q)
    np.savez(C / "arrays" / "two_arrays.npz", a=q, b=q)
    qn = q.copy()
    qn[3] = np.nan
    qn[7, 2] = np.inf
    np.save(C / "arrays" / "joints_with_nan_rows.npy", qn)
    Tn = T.copy()
    Tn[5] = np.nan
    np.save(C / "arrays" / "poses_with_nan_row.npy", Tn)
    np.save(C / "arrays" / "poses_complex.npy", T.astype(complex))
    np.save(C / "arrays" / "joints_complex.npy", q.astype(complex))
    np.save(C / "arrays" / "joints_wrong_shape.npy", q[:, :5])
    np.save(C / "arrays" / "joints_strings.npy", np.array([["a"] * 6] * 3))
    np.save(C / "arrays" / "joints_object.npy", np.array([[1, 2, 3, 4, 5, None]] * 2, dtype=object),
            allow_pickle=True)
    buf = io.BytesIO()
    np.save(buf, q)
    raw("arrays", "joints_truncated.npy", buf.getvalue()[:200])
    raw("arrays", "joints_header_only.npy", buf.getvalue()[:128])
    raw("arrays", "not_an_array.npy", b"hello world\n")
    with zipfile.ZipFile(C / "arrays" / "broken.npz", "w") as zf:
        zf.writestr("T.npy", b"\x93NUMPY garbage")
    print(f"corpus written to {C}")


if __name__ == "__main__":
    main()
