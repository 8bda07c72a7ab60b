"""Reading input text files (robot files, path CSV): a size limit checked before reading, UTF-8
with or without a byte-order mark, and errors that name the file.

>>> decode_text(b"\\xef\\xbb\\xbfname = 1", "r.toml")
'name = 1'
"""

from __future__ import annotations

from pathlib import Path

from .errors import RobotFileError

__all__ = ["read_bytes_limited", "decode_text", "read_text_file"]


def read_bytes_limited(path, max_bytes: int, what: str, error=RobotFileError) -> bytes:
    """The bytes of ``path``, refusing files larger than ``max_bytes`` (``error``, a
    ``ValueError`` class, naming the size and the keyword that raises the limit) and reporting
    read errors with the file name."""
    p = Path(path)
    try:
        size = p.stat().st_size
        if size > max_bytes:
            raise error(f"{p}: {size:,} bytes; a {what} may have at most {max_bytes:,} "
                                 f"(raise it with max_bytes=)")
        with p.open("rb") as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"{p}: cannot read the {what} ({exc.strerror or exc})") from exc
    if len(data) > max_bytes:
        raise error(f"{p}: more than {max_bytes:,} bytes; too big for a {what}")
    return data


def decode_text(data: bytes, source: str, what: str = "file", error=RobotFileError) -> str:
    """UTF-8 text (a leading byte-order mark is dropped); anything else raises ``error`` (a
    ``ValueError`` class) naming the file and the encoding expected."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        hint = " (it looks like UTF-16)" if data[:2] in (b"\xff\xfe", b"\xfe\xff") else ""
        raise error(f"{source}: the {what} is not UTF-8 text{hint}: byte {exc.start} "
                             f"(0x{data[exc.start]:02x}) cannot be decoded; save it as UTF-8") from None


def read_text_file(path, max_bytes: int, what: str) -> str:
    """:func:`read_bytes_limited` then :func:`decode_text`."""
    return decode_text(read_bytes_limited(path, max_bytes, what), str(path), what)
