"""Running ``ik7r`` in-process (``ik7r.cli.main``) and checking the shape of its answer."""

from __future__ import annotations

import contextlib
import io

from ik7r.cli import main


def run_cli(*argv: str) -> tuple[int, str, str]:
    """``(exit status, stdout, stderr)`` of ``ik7r argv`` run in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def assert_well_behaved(code: int, err: str, allowed=(0, 1, 2)) -> None:
    """Exit status documented, no traceback, at most two lines on stderr."""
    assert code in allowed, (code, err)
    assert "Traceback" not in err, err
    assert len(err.splitlines()) <= 2, err
