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
