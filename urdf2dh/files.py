"""Reading input files and writing output files, with one-line errors naming the file.

Output goes to stdout, or to ``-o FILE``:

* a regular file (new or existing, or the regular file a symbolic link points to) is written
  through a temporary file beside it and a rename, keeping an existing file's permissions; a
  failed or interrupted run (an error, Ctrl-C, SIGTERM) removes the temporary file and leaves
  the old file as it was;
* a character device or a FIFO (``/dev/null``, ``/dev/stdout``, a pipe) is written straight
  into: it cannot be replaced, only written;
* anything else (a directory, a socket, a dangling link) and the SOURCE file itself are refused.

A failed write, to stdout included (a full disk, ``> /dev/full``), is an error (exit 2), never
silent: every text the commands print goes through :func:`write_stdout`, and
:func:`flush_stdout` ends each run. A reader that goes away (``| head``) is not an error.

Several files go to ``-o DIR`` (:func:`write_directory`), all or nothing:

* DIR is an existing directory (or a link to one), or a new name in an existing directory;
* each file's place in DIR must be free or hold a regular file, which is replaced keeping its
  permissions; a symbolic link, directory, device or FIFO there, or the SOURCE file, is refused
  before anything is written;
* the files are written into a temporary directory first: for a new DIR one beside it, renamed
  to DIR at the end (so DIR appears only on success, complete); for an existing DIR a hidden one
  inside it, whose files are then renamed into DIR (one file system, so each rename is atomic;
  should one fail, the files already moved are taken back and the replaced ones restored from
  hard links where the file system makes them). The temporary directory never outlives the run.
"""

from __future__ import annotations

import os
import shutil
import stat
import sys
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path

from .errors import InputError

__all__ = [
    "drop_stdout",
    "flush_stdout",
    "read_file",
    "write_directory",
    "write_output",
    "write_stdout",
]


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
        write_stdout(raw)
        return
    target = Path(output)
    _refuse_source(target, output, sources)
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


def write_stdout(data: str | bytes) -> None:
    """Write ``data`` to stdout now (UTF-8), or raise ``InputError("stdout: cannot write
    (...)")``; a ``BrokenPipeError`` (the reader went away) is raised as it is, not an error of
    ours."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    try:
        sys.stdout.flush()
        buffer = getattr(sys.stdout, "buffer", None)
        if buffer is None:  # a text-only stream (io.StringIO in place of stdout)
            sys.stdout.write(raw.decode("utf-8", "replace"))
        else:
            buffer.write(raw)
            buffer.flush()
    except BrokenPipeError:
        raise
    except OSError as e:
        raise _stdout_failed(e) from e


def flush_stdout() -> None:
    """Flush stdout: what is still buffered is written, or ``InputError`` as
    :func:`write_stdout` raises it."""
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        raise
    except OSError as e:
        raise _stdout_failed(e) from e


def drop_stdout() -> None:
    """Point stdout's file descriptor at the null device, so that nothing more reaches a reader
    that went away or a full device (and Python's own flush at exit does not fail again)."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # no descriptor (a stream in its place)
        pass


def _stdout_failed(e: OSError) -> InputError:
    drop_stdout()
    return InputError(f"stdout: cannot write ({e.strerror or e})")


def _refuse_source(target: Path, shown: str, sources: Iterable[str]) -> None:
    """An ``InputError`` if ``target`` is one of the command's input files."""
    for source in sources:
        if _same_file(target, Path(source)):
            raise InputError(f"{shown}: is the SOURCE file; refusing to write over it")


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
            os.chmod(tmp, 0o666 & ~_umask())
        else:  # keep the permissions of the file replaced
            os.chmod(tmp, stat.S_IMODE(mode))
        os.replace(tmp, target)
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    finally:  # an error, KeyboardInterrupt or SystemExit (SIGTERM, see cli.py) alike
        Path(tmp).unlink(missing_ok=True)


# --------------------------------------------------------------------------- -o DIR


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _existing_modes(
    directory: Path, names: Iterable[str], output: str, sources: Iterable[str]
) -> dict[str, int | None]:
    """Each file name -> the permissions of the regular file it replaces (``None``: new); what
    must not be replaced is refused here, before anything is written."""
    modes: dict[str, int | None] = {}
    for name in names:
        target = directory / name
        shown = os.path.join(output, name)
        _refuse_source(target, shown, sources)
        try:
            mode = os.lstat(target).st_mode
        except FileNotFoundError:
            modes[name] = None
            continue
        except OSError as e:
            raise InputError(f"{shown}: cannot write ({e.strerror})") from e
        if not stat.S_ISREG(mode):
            raise InputError(f"{shown}: is not a regular file; refusing to replace it")
        modes[name] = stat.S_IMODE(mode)
    return modes


def _stage(staging: Path, files: Mapping[str, bytes], modes: Mapping[str, int | None]) -> None:
    for name, raw in files.items():
        fd = os.open(staging / name, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        mode = modes[name]
        if mode is not None:
            os.chmod(staging / name, mode)


def _move_in(staging: Path, directory: Path, modes: Mapping[str, int | None]) -> None:
    """Rename the staged files into ``directory``; on a failure put back what was there."""
    backups = staging / "old"
    backups.mkdir()
    done: list[tuple[Path, Path | None]] = []
    try:
        for name, mode in modes.items():
            target, backup = directory / name, None
            if mode is not None:
                try:
                    os.link(target, backups / name)
                    backup = backups / name
                except OSError:  # no hard links here: this file cannot be restored
                    pass
            os.replace(staging / "new" / name, target)
            done.append((target, backup))
    except BaseException:
        for target, backup in reversed(done):
            try:
                if backup is None:
                    target.unlink()
                else:
                    os.replace(backup, target)
            except OSError:
                pass
        raise


def write_directory(
    files: Mapping[str, str | bytes], output: str, sources: Iterable[str] = ()
) -> None:
    """Write each ``name -> data`` to ``output/name``, all or nothing (see the module docstring).

    Parameters
    ----------
    files
        File name (a plain name, no directory part) -> its text or bytes.
    output
        The directory, as the user named it (also in messages).
    sources
        The command's input files: none of the files may be one of them.
    """
    for name in files:
        if name in ("", ".", "..") or os.sep in name or "/" in name or "\0" in name:
            raise ValueError(f"not a plain file name: {name!r}")
    if not output:
        raise InputError("-o: an empty directory name")
    raw = {n: d.encode("utf-8") if isinstance(d, str) else d for n, d in files.items()}
    directory = Path(output)
    exists = directory.is_dir()
    if exists:
        directory = directory.resolve()
    elif directory.is_symlink():
        raise InputError(f"{output}: is a dangling symbolic link; refusing to write")
    elif directory.exists():
        raise InputError(f"{output}: is not a directory; several files need -o DIR")
    elif not directory.absolute().parent.is_dir():
        raise InputError(f"{output}: directory '{directory.absolute().parent}' does not exist")
    modes = _existing_modes(directory, raw, output, sources) if exists else dict.fromkeys(raw)
    try:
        where = directory if exists else directory.absolute().parent
        tmp = Path(tempfile.mkdtemp(prefix=f".{directory.name or 'output'}.", dir=where))
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    try:
        if exists:
            (tmp / "new").mkdir()
            _stage(tmp / "new", raw, modes)
            _move_in(tmp, directory, modes)
        else:
            _stage(tmp, raw, modes)
            os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; mkdir would give this
            os.rename(tmp, directory)  # DIR appears now, complete
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    finally:  # an error, KeyboardInterrupt or SystemExit (SIGTERM, see cli.py) alike
        shutil.rmtree(tmp, ignore_errors=True)
