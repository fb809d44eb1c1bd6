"""Reading input files and writing output files, with one-line errors naming the file.

Output goes to stdout, or to ``-o FILE``:

* a regular file (new or existing, or the regular file a symbolic link points to) is written
  through a temporary file beside it and a rename, keeping an existing file's permissions; a
  failed or interrupted run (an error, Ctrl-C, SIGTERM) removes the temporary file and leaves
  the old file as it was;
* a character device or a FIFO (``/dev/null``, ``/dev/stdout``, a pipe) is written straight
  into: it cannot be replaced, only written;
* anything else (a directory, a socket, a dangling link) and the SOURCE file itself are refused.

A failed write, to stdout included (a full disk), is an error (exit 2), never silent.
"""

from __future__ import annotations

import os
import stat
import sys
import tempfile
from collections.abc import Iterable
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


def write_output(data: str | bytes, output: str | None, sources: Iterable[str] = ()) -> None:
    """Write ``data`` to stdout, or to ``output`` (see the module docstring). ``sources`` are the
    command's input files: ``output`` may not be one of them."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    if output is None:
        try:
            sys.stdout.flush()
            buffer = getattr(sys.stdout, "buffer", None)
            if buffer is None:  # a text-only stream (io.StringIO in place of stdout)
                sys.stdout.write(raw.decode("utf-8", "replace"))
            else:
                buffer.write(raw)
                buffer.flush()
        except BrokenPipeError:
            raise  # the reader went away (`| head`): not an error of ours
        except OSError as e:
            raise InputError(f"stdout: cannot write ({e.strerror})") from e
        return
    target = Path(output)
    for source in sources:
        if _same_file(target, Path(source)):
            raise InputError(f"{output}: is the SOURCE file; refusing to write over it")
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        if target.is_symlink():
            raise InputError(f"{output}: is a dangling symbolic link; refusing to write") from None
        mode = None
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    if mode is not None and (stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)):
        _write_into(target, raw, output)
    elif mode is not None and not stat.S_ISREG(mode):
        raise InputError(f"{output}: is not a regular file; refusing to replace it")
    else:
        _replace(target.resolve() if mode is not None else target, raw, output, mode)


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _write_into(target: Path, raw: bytes, output: str) -> None:
    """Write straight into a device or FIFO."""
    try:
        with open(target, "wb") as f:
            f.write(raw)
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e


def _replace(target: Path, raw: bytes, output: str, mode: int | None) -> None:
    """Write a temporary file beside ``target`` and rename it into place; on any failure or
    interruption the temporary file is removed and ``target`` is untouched."""
    directory = target.parent
    if not directory.is_dir():
        raise InputError(f"{output}: directory '{directory}' does not exist")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=directory)
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        if mode is None:  # mkstemp creates 0600; give it the mode a plain open() would
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
        else:  # keep the permissions of the file replaced
            os.chmod(tmp, stat.S_IMODE(mode))
        os.replace(tmp, target)
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    finally:  # an error, KeyboardInterrupt or SystemExit (SIGTERM, see cli.py) alike
        Path(tmp).unlink(missing_ok=True)
