"""ik7r._kernels.jit: one notice on stderr before a compile (never when the cache is warm), and one
compiled specialisation per kernel whatever constants its callers pass."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

pytest.importorskip("numba")

KERNELS = textwrap.dedent('''
    from ik7r._kernels.jit import njit

    @njit
    def scale(x, k):
        return x * k

    @njit
    def entry(x):
        n = 2
        return scale(x, 3) + scale(x, n) + scale(x, 1)   # literal 3, int64, literal 1
''')

DRIVER = textwrap.dedent('''
    import sys
    sys.path.insert(0, sys.argv[1])
    import kernels_for_test as k
    print(k.entry(2))
    print(len(k.scale.signatures), k.scale.signatures[:1])   # none when entry came from the cache
''')


def _run(tmp_path, **env):
    (tmp_path / "kernels_for_test.py").write_text(KERNELS)
    full = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), **env}
    if "IK7R_QUIET" not in env:
        full.pop("IK7R_QUIET", None)
    return subprocess.run([sys.executable, "-c", DRIVER, str(tmp_path)], capture_output=True, text=True,
                          env=full, timeout=600)


def test_a_cold_cache_says_so_once_and_a_warm_one_is_silent(tmp_path):
    first = _run(tmp_path)
    assert first.returncode == 0, first.stderr
    assert first.stdout.split()[0] == "12"                   # 6 + 4 + 2
    notices = [line for line in first.stderr.splitlines() if line.startswith("ik7r: compiling")]
    assert len(notices) == 1 and "entry" in notices[0] and "once" in notices[0]
    second = _run(tmp_path)                                  # the cache is filled now
    assert second.returncode == 0, second.stderr
    assert "ik7r: compiling" not in second.stderr


def test_the_notice_can_be_silenced(tmp_path):
    p = _run(tmp_path, IK7R_QUIET="1")
    assert p.returncode == 0, p.stderr
    assert "ik7r: compiling" not in p.stderr


def test_constant_arguments_share_one_specialisation(tmp_path):
    p = _run(tmp_path, IK7R_QUIET="1")
    count, signature = p.stdout.splitlines()[1].split(" ", 1)
    assert count == "1", p.stdout                            # not one per literal 3 / 1
    assert "Literal" not in signature and signature.count("int64") == 2


CALLEE = "from ik7r._kernels.jit import njit\n\n@njit\ndef scale(x):\n    return x * {k}\n"
CALLER = textwrap.dedent('''
    from ik7r._kernels.jit import njit
    from callee_for_test import scale

    @njit
    def entry(x):
        return scale(x) + 1
''')
STAMPED_DRIVER = textwrap.dedent('''
    import os, sys
    sys.path.insert(0, sys.argv[1])
    import ik7r._kernels.jit as jit
    # the two files of this test stand for the kernel sources
    jit._kernel_sources = lambda: tuple(os.path.realpath(os.path.join(sys.argv[1], f))
                                        for f in ("callee_for_test.py", "caller_for_test.py"))
    import caller_for_test
    print(caller_for_test.entry(2))
''')


def test_an_edited_callee_recompiles_its_cached_caller(tmp_path):
    """A kernel cached with the code of a kernel it calls from another file runs the edited
    callee after an edit of that file alone (numba's own stamp is the caller's file: it ran
    the old code)."""
    (tmp_path / "caller_for_test.py").write_text(CALLER)
    results = []
    for k in (3, 5):
        (tmp_path / "callee_for_test.py").write_text(CALLEE.format(k=k))
        env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "IK7R_QUIET": "1"}
        p = subprocess.run([sys.executable, "-c", STAMPED_DRIVER, str(tmp_path)], capture_output=True,
                           text=True, env=env, timeout=600)
        assert p.returncode == 0, p.stderr
        results.append(int(p.stdout.split()[0]))
    assert results == [7, 11]                                # 2 * 3 + 1, then 2 * 5 + 1


def test_every_kernel_source_enters_the_stamp(tmp_path):
    from ik7r._kernels.jit import sources_stamp

    files = [tmp_path / f"k{i}.py" for i in range(3)]
    for f in files:
        f.write_text("x = 1\n")
    before = sources_stamp(files)
    assert sources_stamp(files) == before
    for i, f in enumerate(files):
        f.write_text(f"x = {i + 2}\n")                       # (another size: a new key)
        after = sources_stamp(files)
        assert after != before
        before = after
