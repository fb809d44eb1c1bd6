"""Reading input files and writing output files, with one-line errors naming the file.

Output is written to a temporary file in the target's directory and renamed into place, so a
failure never leaves a partial file behind (SPEC §1).
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

from .errors import InputError

__all__ = ["read_file", "write_output"]


def read_file(path: Path, display: str) -> bytes:
    """The bytes of ``path``; ``display`` names it in error messages."""
    try:
        with open(path, "rb", buffering=0) as f:  # unbuffered: one read of the whole file
            return f.read()
    except FileNotFoundError as e:
        raise InputError(f"{display}: no such file") from e
    except IsADirectoryError as e:
        raise InputError(f"{display}: is a directory, not a file") from e
    except OSError as e:
        raise InputError(f"{display}: cannot read ({e.strerror})") from e


def write_output(data: str | bytes, output: str | None) -> None:
    """Write ``data`` to stdout, or atomically to ``output`` (temporary file, then rename)."""
    if output is None:
        if isinstance(data, bytes):
            sys.stdout.buffer.write(data)
        else:
            sys.stdout.write(data)
        return
    target = Path(output)
    directory = target.parent
    if not directory.is_dir():
        raise InputError(f"{output}: directory '{directory}' does not exist")
    raw = data.encode("utf-8") if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=directory)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        # mkstemp creates 0600; give the file the mode a plain open() would (0666 - umask)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target)
    except OSError as e:
        Path(tmp).unlink(missing_ok=True)
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
