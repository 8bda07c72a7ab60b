"""Atomic, honest outputs: a file is either complete or absent, a results directory gets its
manifest last.

Two tools, used by every command that writes files:

- :func:`atomic_file` writes one file under a temporary name in the file's own directory
  (``.NAME.ik7r-tmp-XXXX``), flushes it to disk and renames it over ``NAME`` when complete
  (``os.replace``: readers see the old file or the new one, never a part). On any error, or an
  interrupt, the temporary file is removed and ``NAME`` is left as it was.
- :class:`OutputDir` stages the files of a results directory in a hidden staging directory
  inside the target (``DIR/.ik7r-staging-XXXX``, so the renames never cross a file system)
  and publishes them with ``os.replace`` when the run completes, its *manifest* (``meta.json``,
  ``report.md``, ``report.txt``) last. Entering it first removes the manifest of a previous run
  in the target, so from then on the directory does not look complete until the new run has
  finished. On an error or an interrupt the staging directory is removed, and the target
  directory too when the run created it and it is empty.

>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as tmp:
...     with OutputDir(pathlib.Path(tmp) / "run", manifest="meta.json") as out:
...         _ = (out.path / "data.txt").write_text("42")
...         _ = (out.path / "meta.json").write_text("{}")
...     sorted(p.name for p in (pathlib.Path(tmp) / "run").iterdir())
['data.txt', 'meta.json']

:func:`signals_raise` makes SIGTERM (and SIGHUP) raise :class:`Terminated` in the main thread,
so that these clean-ups run when a pipeline stops ``ik7r`` (SIGINT raises KeyboardInterrupt
already); the command line installs it.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

from .errors import Ik7rError

__all__ = ["atomic_file", "atomic_path", "write_text_atomic", "OutputDir", "Terminated", "signals_raise",
           "OutputError", "describe_os_error"]

_TMP_MARK = ".ik7r-tmp-"
_STAGE_MARK = ".ik7r-staging-"


class Terminated(BaseException):
    """The process received SIGTERM or SIGHUP (raised in the main thread by :func:`signals_raise`).

    A ``BaseException`` like ``KeyboardInterrupt``, so ``except Exception`` does not swallow it.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class OutputError(Ik7rError, OSError):
    """An output could not be written (full disk, read-only place, a file where a directory is
    expected); the message names the path and the reason."""


def describe_os_error(exc: OSError, path) -> str:
    """One line: what went wrong writing ``path``."""
    if exc.errno == errno.ENOSPC:
        why = "no space left on the device"
    elif exc.errno == errno.EDQUOT:
        why = "disk quota exceeded"
    elif exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        why = "permission denied (read-only place?)"
    else:
        why = exc.strerror or str(exc)
    return f"cannot write {path}: {why}"


def _set_handlers(names: tuple[str, ...], handler: Callable[[int, Any], Any]) -> dict[int, Any]:
    """Install ``handler`` for each signal of ``names`` the platform has (one that may not be set
    here is left alone); returns the handlers it replaced, by signal number."""
    old = {}
    for name in names:
        num = getattr(signal, name, None)
        if num is None:
            continue
        try:
            old[num] = signal.signal(num, handler)
        except (ValueError, OSError):  # pragma: no cover - not allowed here
            pass
    return old


@contextlib.contextmanager
def _deferred_signals() -> Iterator[None]:
    """Hold SIGINT/SIGTERM/SIGHUP while the block runs (publishing or cleaning up), then deliver
    the first one that came. Outside the main thread it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    old = _set_handlers(("SIGINT", "SIGTERM", "SIGHUP"), lambda n, f: pending.append(n))
    try:
        yield
    finally:
        for num, handler in old.items():
            signal.signal(num, handler)
        if pending:
            first = pending[0]
            handler = old.get(first)
            if callable(handler):
                handler(first, None)
            elif first == signal.SIGINT:
                raise KeyboardInterrupt
            else:
                raise Terminated(first)


def _fsync(fd: int) -> None:
    with contextlib.suppress(OSError):
        os.fsync(fd)


@contextlib.contextmanager
def atomic_file(path, mode: str = "w", **open_kw) -> Iterator:
    """Open ``path`` for writing through a temporary file renamed over it when the block ends.

    Parameters
    ----------
    path : str or Path
        The final file. Its directory must exist.
    mode : {"w", "wb"}
        Text or binary.
    **open_kw
        Passed to :func:`open` (``encoding``, ``newline``).

    Yields
    ------
    file
        The open temporary file (its name is ``file.name``).

    Raises
    ------
    OutputError
        The file cannot be written (the message names it and says why).
    """
    path = Path(path)
    if mode not in ("w", "wb"):
        raise ValueError(f"mode must be 'w' or 'wb'; got {mode!r}")
    if path.is_dir():
        raise OutputError(errno.EISDIR, f"cannot write {path}: it is a directory")
    if "b" not in mode:
        open_kw.setdefault("encoding", "utf-8")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}{_TMP_MARK}", dir=path.parent or ".")
    except OSError as exc:
        raise OutputError(exc.errno, describe_os_error(exc, path)) from exc
    done = False
    try:
        try:
            os.close(fd)  # reopened by name, so that ``fh.name`` is the temporary path
            with open(tmp, mode, **open_kw) as fh:
                yield fh
                if not fh.closed:
                    fh.flush()
                    _fsync(fh.fileno())
            with _deferred_signals():
                os.chmod(tmp, 0o666 & ~_umask())
                os.replace(tmp, path)
                done = True
        except OSError as exc:
            if isinstance(exc, OutputError):
                raise
            raise OutputError(exc.errno, describe_os_error(exc, path)) from exc
    finally:
        if not done:
            with _deferred_signals(), contextlib.suppress(OSError):
                os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path) -> Iterator[Path]:
    """A temporary path beside ``path`` for a writer that takes a file name; renamed over
    ``path`` when the block ends normally, removed otherwise (see :func:`atomic_file`)."""
    path = Path(path)
    with atomic_file(path, "wb") as fh:
        fh.close()  # the writer opens the name itself
        yield Path(fh.name)


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`atomic_file`); returns the path."""
    with atomic_file(path, "w") as fh:
        fh.write(text)
    return Path(path)


class OutputDir:
    """A results directory written atomically: files staged, published on success, manifest last.

    Parameters
    ----------
    target : str or Path
        The results directory (created when missing; an existing file there is an error).
    manifest : str or iterable of str
        Names of the files that say the run is complete (``meta.json``, ``report.md``); they are
        removed from the target on entry and published after every other file.
    owned : iterable of str, optional
        Names of the files this kind of run writes: those the new run does not write are
        removed from the target when it publishes (so an old ``joints.npy`` does not sit beside
        a new ``q.npy``). Other files of the target are never touched.

    Use it as a context manager; write the files into :attr:`path` (the staging directory).
    Leaving the block normally publishes them; an exception (an error, ``KeyboardInterrupt``,
    :class:`Terminated`) removes them. :meth:`publish` may also be called inside the block.
    """

    def __init__(self, target, manifest: str | Iterable[str] = (), owned: Iterable[str] = ()) -> None:
        self.target = Path(target)
        self.manifest = (manifest,) if isinstance(manifest, str) else tuple(manifest)
        self.owned = frozenset(owned) | frozenset(self.manifest)
        self.path: Path | None = None
        self._created = False
        self._published = False

    def __enter__(self) -> OutputDir:
        t = self.target
        if t.exists() and not t.is_dir():
            raise OutputError(errno.ENOTDIR, f"cannot write into {t}: it exists and is not a directory")
        try:
            if not t.exists():
                t.mkdir(parents=True)
                self._created = True
            for name in self.manifest:  # the old run no longer looks complete
                old = t / name
                if old.is_file() or old.is_symlink():
                    old.unlink()
            self.path = Path(tempfile.mkdtemp(prefix=_STAGE_MARK, dir=t))
        except OSError as exc:
            self._cleanup()
            raise OutputError(exc.errno, describe_os_error(exc, t)) from exc
        return self

    def publish(self) -> list[Path]:
        """Move the staged files into the target (manifest last); returns their final paths."""
        if self._published:
            return []
        assert self.path is not None, "publish() inside the with block"
        staged = sorted(p.name for p in self.path.iterdir())
        order = [n for n in staged if n not in self.manifest] + [n for n in self.manifest if n in staged]
        published = []
        try:
            with _deferred_signals():
                for name in self.owned - set(staged):  # stale files of an older run
                    old = self.target / name
                    if old.is_file() or old.is_symlink():
                        old.unlink()
                for name in order:
                    src, dst = self.path / name, self.target / name
                    if dst.is_dir() and not src.is_dir():
                        raise OutputError(errno.EISDIR, f"cannot write {dst}: it is a directory")
                    if src.is_dir():
                        if dst.is_dir():
                            shutil.rmtree(dst)
                    os.replace(src, dst)
                    published.append(dst)
                self.path.rmdir()
                self._published = True
        except OSError as exc:
            if isinstance(exc, OutputError):
                raise
            raise OutputError(exc.errno, describe_os_error(exc, self.target)) from exc
        return published

    def _cleanup(self) -> None:
        with _deferred_signals():
            if self.path is not None and self.path.exists():
                shutil.rmtree(self.path, ignore_errors=True)
            if self._created and not self._published:
                with contextlib.suppress(OSError):
                    self.target.rmdir()  # only when empty

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            try:
                self.publish()
            except BaseException:
                self._cleanup()
                raise
        else:
            self._cleanup()
        if isinstance(exc, OSError) and not isinstance(exc, OutputError):
            raise OutputError(exc.errno, describe_os_error(exc, self.target)) from exc


@contextlib.contextmanager
def signals_raise() -> Iterator[None]:
    """Inside the block SIGTERM and SIGHUP raise :class:`Terminated` in the main thread (so
    ``finally`` blocks and :class:`OutputDir` clean up); outside the main thread, nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Terminated(signum)

    old = _set_handlers(("SIGTERM", "SIGHUP"), handler)
    try:
        yield
    finally:
        for num, h in old.items():
            signal.signal(num, h)
