"""Reading input files and writing output files, with one-line errors naming the file.

Inputs: within :func:`one_run` (the command line's run), every file the run reads is one of its
inputs: what :func:`read_file` reads (SOURCE, a bundled robot's installed file, measurements,
a marker layout) and what :func:`note_input` is told of (every file a xacro expansion opened).
No output of the run may be one of them, whatever name it is given (a symbolic link, a hard
link, another path to it).

Outputs go to stdout or to files, all of a run's together (:func:`write_outputs`;
:func:`write_output` for one):

* a regular file (new or existing, or the regular file a symbolic link points to) is written
  through a temporary file beside it and a rename, keeping an existing file's permissions;
* a character device or a FIFO (``/dev/null``, ``/dev/stdout``, a pipe) is written straight
  into: it cannot be replaced, only written (before any file is put in place);
* anything else (a directory, a socket, a dangling link), an input of the run, and two outputs
  that are the same file (but for a device or FIFO) are refused, before anything is written.

All or nothing: every file is written to its temporary file first; only then are they renamed
into place, with Ctrl-C and ``SIGTERM`` held off (:func:`urdf2dh.io.interrupts.committing`); should
a rename fail, those done are undone, the replaced files restored from hard links where the file
system makes them. A failed or interrupted run (an error, Ctrl-C, ``SIGTERM``) leaves every file
as it was, and no temporary file behind. A failed write, to stdout included (a full disk,
``> /dev/full``), is an error (exit 2), never silent: every text the commands print goes through
:func:`write_stdout`, and :func:`flush_stdout` ends each run. A reader that goes away (``| head``)
is not an error. A standard stream the program was started without (``>&-``, ``2>&-``) is
given the null device by :func:`standard_streams`, so that no file the run opens takes its
number; text for a closed stdout is a failed write like any other, text for a closed stderr is
dropped (the exit code still tells).

Several files go to ``-o DIR`` (:func:`write_directory`), all or nothing too: DIR is an existing
directory (or a link to one), or a new name in an existing directory; each file's place in DIR
must be free or hold a regular file (a symbolic link, directory, device or FIFO there is
refused). A new DIR is written as a temporary directory beside it, renamed to DIR at the end: it
appears only on success, complete.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import select
import stat
import sys
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..tolerances import FILE_BYTES
from . import interrupts

__all__ = [
    "check_outputs",
    "drop_stdout",
    "flush_stdout",
    "note_input",
    "one_run",
    "read_file",
    "standard_streams",
    "write_directory",
    "write_output",
    "write_outputs",
    "write_stdout",
]

SOURCE_ROLE = "the SOURCE file"
INPUT_ROLE = "an input of this run"

# the inputs of the run: (device, inode) -> what the file is to the run ("the SOURCE file")
_inputs: ContextVar[dict[tuple[int, int], str] | None] = ContextVar("inputs", default=None)


# --------------------------------------------------------------------------- inputs


@contextlib.contextmanager
def one_run() -> Iterator[None]:
    """A run: the files read within are its inputs, and no output replaces one of them."""
    token = _inputs.set({})
    try:
        yield
    finally:
        _inputs.reset(token)


def _record(status: os.stat_result, role: str) -> None:
    inputs = _inputs.get()
    if inputs is not None:
        inputs.setdefault((status.st_dev, status.st_ino), role)


def note_input(path: str | Path, role: str = INPUT_ROLE) -> None:
    """Record ``path`` (read by other means than :func:`read_file`) as an input of the run; a
    path that does not exist (any more) is left out."""
    try:
        _record(os.stat(path), role)
    except (OSError, ValueError):
        pass


def read_file(path: Path, display: str, role: str = INPUT_ROLE, limit: int = FILE_BYTES) -> bytes:
    """The bytes of the regular file ``path``, an input of the run (``role`` says what it is to
    the run), at most ``limit`` of them (:data:`~urdf2dh.tolerances.FILE_BYTES`); ``display`` names
    it in error messages.

    A device, FIFO or socket (``/dev/zero``, a named pipe, ``/dev/stdin``) is refused before
    anything is read: it may never end, or block forever (the file is opened without waiting for
    a writer, and checked again once open). At most one byte beyond the limit is read, so a file
    that grows while it is read is bounded too."""
    try:
        _regular(os.stat(path).st_mode, display)
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError as e:
        raise InputError(f"{display}: no such file") from e
    except OSError as e:
        raise InputError(f"{display}: cannot read ({e.strerror})") from e
    with os.fdopen(fd, "rb", buffering=0) as f:
        status = os.fstat(fd)
        _regular(status.st_mode, display)  # the file opened, should the path have moved
        _record(status, role)
        chunks, total = [], 0
        try:
            while total <= limit:
                chunk = f.read(limit + 1 - total)
                if not chunk:
                    break
                chunks.append(chunk)
                total += len(chunk)
        except OSError as e:
            raise InputError(f"{display}: cannot read ({e.strerror})") from e
    if total > limit:
        raise InputError(f"{display}: larger than {_size(limit)}, the most urdf2dh reads")
    return b"".join(chunks)


def _regular(mode: int, display: str) -> None:
    if stat.S_ISDIR(mode):
        raise InputError(f"{display}: is a directory, not a file")
    if not stat.S_ISREG(mode):
        raise InputError(
            f"{display}: not a regular file (a device, FIFO or socket); urdf2dh reads files"
        )


def _size(size: int) -> str:
    return f"{size // 2**20} MiB" if size % 2**20 == 0 else f"{size:,} bytes"


def _input_role(status: os.stat_result) -> str | None:
    inputs = _inputs.get()
    return None if inputs is None else inputs.get((status.st_dev, status.st_ino))


# --------------------------------------------------------------------------- one output file


@dataclass(frozen=True, slots=True)
class _Plan:
    """Where one output goes, checked before anything is written."""

    shown: str  # as the user named it (messages)
    target: Path  # the file replaced or created (a symbolic link's target)
    mode: int | None  # the permissions of the regular file replaced; None: a new file
    stream: bool  # a character device or FIFO: written into
    identity: tuple[int, int] | tuple[str]  # the same file <=> the same identity
    owner: tuple[int, int] | None = None  # user and group of the regular file replaced


def _plan(output: str, in_directory: bool = False) -> _Plan:
    """Check the output ``output``: where it goes, or an ``InputError`` saying why not.
    ``in_directory``: a file of ``-o DIR``, which must be free or a regular file."""
    if not output:
        raise InputError("-o: an empty file name")
    path = Path(output)
    try:
        status = os.lstat(path) if in_directory else os.stat(path)
    except FileNotFoundError:
        if path.is_symlink():
            raise InputError(f"{output}: is a dangling symbolic link; refusing to write") from None
        directory = path.absolute().parent
        if not directory.is_dir():
            raise InputError(f"{output}: directory '{directory}' does not exist") from None
        target = directory.resolve() / path.name
        return _Plan(output, target, None, False, (str(target),))
    except OSError as e:
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    role = _input_role(status)
    if role is not None:
        raise InputError(f"{output}: is {role}; refusing to write over it")
    identity = (status.st_dev, status.st_ino)
    if not in_directory and (stat.S_ISCHR(status.st_mode) or stat.S_ISFIFO(status.st_mode)):
        return _Plan(output, path, None, True, identity)
    if not stat.S_ISREG(status.st_mode):
        raise InputError(f"{output}: is not a regular file; refusing to replace it")
    owner = (status.st_uid, status.st_gid)
    return _Plan(output, path.resolve(), stat.S_IMODE(status.st_mode), False, identity, owner)


def _plan_all(outputs: Iterable[str], in_directory: bool = False) -> list[_Plan]:
    plans: list[_Plan] = []
    for output in outputs:
        plan = _plan(output, in_directory)
        for other in plans:
            if other.identity == plan.identity and not plan.stream:  # /dev/null twice is fine
                raise InputError(
                    f"{plan.shown}: is the same file as {other.shown}; two outputs of one run "
                    "cannot go to one file"
                )
        plans.append(plan)
    return plans


def check_outputs(outputs: Iterable[str | None]) -> None:
    """Refuse now what :func:`write_outputs` would refuse of these outputs (``None``: stdout):
    a run that takes long can fail before its work rather than after it."""
    _plan_all(o for o in outputs if o is not None)


# --------------------------------------------------------------------------- writing


def write_output(data: str | bytes, output: str | None) -> None:
    """Write ``data`` to stdout, or to the file ``output`` (see the module docstring)."""
    write_outputs([(output, data)])


def write_outputs(outputs: Sequence[tuple[str | None, str | bytes]]) -> None:
    """Write each ``(output, data)`` of a run, all or nothing (see the module docstring).

    Parameters
    ----------
    outputs
        The file name as the user gave it (``None``: stdout, at most once) and its text or bytes.
    """
    to_stdout = [_bytes(data) for output, data in outputs if output is None]
    if len(to_stdout) > 1:
        raise ValueError("at most one output of a run goes to stdout")
    files = [(o, _bytes(d)) for o, d in outputs if o is not None]
    _write(files, to_stdout[0] if to_stdout else None)


def _write(
    files: Sequence[tuple[str, bytes]], stdout: bytes | None, in_directory: bool = False
) -> None:
    """Check every output, stage the files, write the streams and stdout, then put the files in
    place (``in_directory``: the files of ``-o DIR``)."""
    plans = _plan_all((o for o, _ in files), in_directory)
    staged: list[tuple[_Plan, Path]] = []
    try:
        with interrupts.held():  # each temporary file is noted as soon as it exists
            for plan, (_, raw) in zip(plans, files, strict=True):
                if not plan.stream:
                    staged.append((plan, _stage(plan, raw)))
        interrupts.check()
        for plan, (_, raw) in zip(plans, files, strict=True):
            if plan.stream:
                _write_into(plan, raw)
        if stdout is not None:
            write_stdout(stdout)
        with interrupts.committing():
            _put_in_place(staged)
    finally:  # an error, KeyboardInterrupt or SystemExit (SIGTERM) alike
        for _, tmp in staged:
            tmp.unlink(missing_ok=True)


def _bytes(data: str | bytes) -> bytes:
    return data.encode("utf-8") if isinstance(data, str) else data


class _Closed(io.TextIOBase):
    """Stands for a standard output the program was started without (``>&-``): every write
    fails, as a write to a closed descriptor would (``EBADF``), with the one-line error of any
    failed write to stdout (``print`` included)."""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        if not text:
            return 0
        raise _stdout_failed(OSError(errno.EBADF, "it is closed"))

    @property
    def buffer(self) -> _Closed:
        return self  # bytes fail the same way


def standard_streams() -> None:
    """Give each standard descriptor (0, 1, 2) that is closed the null device, so that no file
    the run opens is given its number (and a child inherits no file of ours as its stdout).

    ``sys.stdout`` and ``sys.stderr`` left ``None`` by Python for a closed descriptor become
    streams of their own: stdout one whose writes fail (:func:`write_stdout` says ``stdout:
    cannot write (it is closed)``), stderr the null device (messages go nowhere; the exit code
    still tells)."""
    for number, flags in ((0, os.O_RDONLY), (1, os.O_WRONLY), (2, os.O_WRONLY)):
        try:
            os.fstat(number)
        except OSError:
            fd = os.open(os.devnull, flags)
            if fd != number:  # a lower descriptor was closed too: it took that one
                os.dup2(fd, number)
                os.close(fd)
    if sys.stdout is None:
        sys.stdout = _Closed()
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w", encoding="utf-8")  # kept for the program's life


def write_stdout(data: str | bytes) -> None:
    """Write ``data`` to stdout now (UTF-8), or raise ``InputError("stdout: cannot write
    (...)")``; a ``BrokenPipeError`` (the reader went away) is raised as it is, not an error of
    ours."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    try:
        _flush(sys.stdout)
        buffer = getattr(sys.stdout, "buffer", None)
        if buffer is None:  # a text-only stream (io.StringIO in place of stdout)
            sys.stdout.write(raw.decode("utf-8", "replace"))
            return
        _flush(buffer)
        try:
            fd = buffer.fileno()
        except (OSError, ValueError, AttributeError):  # a stream without a descriptor
            buffer.write(raw)
            buffer.flush()
            return
        view = memoryview(raw)
        while view:
            try:
                view = view[os.write(fd, view) :]
            except BlockingIOError:  # a non-blocking stdout, full: wait for its reader
                select.select([], [fd], [])
    except BrokenPipeError:
        raise
    except OSError as e:
        raise _stdout_failed(e) from e


def _flush(stream: Any) -> None:
    """Flush ``stream``, waiting while a non-blocking descriptor beneath it is full (Python's
    own flush would give up and keep the rest, which the program's exit then loses)."""
    while True:
        try:
            stream.flush()
            return
        except BlockingIOError:
            select.select([], [stream.fileno()], [])


def flush_stdout() -> None:
    """Flush stdout: what is still buffered is written, or ``InputError`` as
    :func:`write_stdout` raises it."""
    try:
        _flush(sys.stdout)
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


def _write_into(plan: _Plan, raw: bytes) -> None:
    """Write straight into a device or FIFO."""
    try:
        with open(plan.target, "wb") as f:
            f.write(raw)
    except OSError as e:
        raise InputError(f"{plan.shown}: cannot write ({e.strerror})") from e


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _stage(plan: _Plan, raw: bytes) -> Path:
    """Write ``raw`` to a new temporary file beside the plan's target, with the owner, group and
    permissions the target will have; its path."""
    import tempfile  # only a run that writes a file needs it

    try:
        fd, name = tempfile.mkstemp(prefix=f".{plan.target.name}.", dir=plan.target.parent)
    except OSError as e:
        raise _cannot_write(plan.shown, plan.target.parent, e, plan.mode is not None) from e
    tmp = Path(name)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        if plan.owner is not None:
            _keep_owner(tmp, *plan.owner)
        # mkstemp creates 0600: give it the mode of the file replaced, or the one open() gives
        # (after the owner: a change of owner clears the set-user-ID and set-group-ID bits)
        os.chmod(tmp, 0o666 & ~_umask() if plan.mode is None else plan.mode)
    except BaseException as e:
        tmp.unlink(missing_ok=True)
        if isinstance(e, OSError):
            raise InputError(f"{plan.shown}: cannot write ({e.strerror})") from e
        raise
    return tmp


def _keep_owner(path: Path, uid: int, gid: int) -> None:
    """Give ``path`` the user and group ``uid``, ``gid`` as far as the process may: both (root,
    or the owner already), else the group alone (a group the user is in), else neither (the
    file then belongs to the user who wrote it, as a new file would)."""
    status = os.stat(path)
    if (status.st_uid, status.st_gid) == (uid, gid):
        return
    for user in (uid, -1):
        try:
            os.chown(path, user, gid)
            return
        except PermissionError:
            continue


def _cannot_write(shown: str, directory: Path, e: OSError, exists: bool) -> InputError:
    """The error of a file that cannot be made in ``directory``: it names the directory, which
    is what must be writable (a file is replaced through a new file beside it and a rename)."""
    if e.errno not in (errno.EACCES, errno.EPERM, errno.EROFS):
        return InputError(f"{shown}: cannot write ({e.strerror})")
    why = (
        "; an existing file is replaced by a new file written beside it and renamed, so its "
        "directory must be writable"
        if exists
        else ""
    )
    return InputError(f"{shown}: cannot write in directory '{directory}' ({e.strerror}){why}")


def _put_in_place(staged: Sequence[tuple[_Plan, Path]]) -> None:
    """Rename the staged files onto their targets; should one fail, undo those done."""
    done: list[tuple[Path, Path | None]] = []  # target, hard link to the file it replaced
    try:
        for plan, tmp in staged:
            backup = _keep(plan.target) if plan.mode is not None and len(staged) > 1 else None
            try:
                os.replace(tmp, plan.target)
            except OSError as e:
                if backup is not None:
                    backup.unlink(missing_ok=True)
                raise _cannot_write(plan.shown, plan.target.parent, e, plan.mode is not None) from e
            done.append((plan.target, backup))
    except BaseException:
        for target, backup in reversed(done):
            try:
                if backup is None:
                    target.unlink()  # new: or replaced where no hard link could keep it
                else:
                    os.replace(backup, target)
            except OSError:
                pass
        raise
    finally:
        for _, backup in done:
            if backup is not None:
                backup.unlink(missing_ok=True)


def _keep(target: Path) -> Path | None:
    """A hard link to ``target`` beside it, to put it back from; ``None`` where the file system
    makes none."""
    for _ in range(8):
        backup = target.with_name(f".{target.name}.{os.urandom(6).hex()}.old")
        try:
            os.link(target, backup)
            return backup
        except FileExistsError:
            continue
        except OSError:
            return None
    return None


# --------------------------------------------------------------------------- -o DIR


def write_directory(files: Mapping[str, str | bytes], output: str) -> None:
    """Write each ``name -> data`` to ``output/name``, all or nothing (see the module docstring).

    Parameters
    ----------
    files
        File name (a plain name, no directory part) -> its text or bytes.
    output
        The directory, as the user named it (also in messages).
    """
    for name in files:
        if name in ("", ".", "..") or os.sep in name or "/" in name or "\0" in name:
            raise ValueError(f"not a plain file name: {name!r}")
    if not output:
        raise InputError("-o: an empty directory name")
    directory = Path(output)
    if directory.is_dir():
        paths = [(os.path.join(output, name), _bytes(data)) for name, data in files.items()]
        _write(paths, None, in_directory=True)
        return
    if directory.is_symlink():
        raise InputError(f"{output}: is a dangling symbolic link; refusing to write")
    if directory.exists():
        raise InputError(f"{output}: is not a directory; several files need -o DIR")
    parent = directory.absolute().parent
    if not parent.is_dir():
        raise InputError(f"{output}: directory '{parent}' does not exist")
    import shutil
    import tempfile

    tmp: Path | None = None
    try:
        with interrupts.held():  # the temporary directory is noted as soon as it exists
            tmp = Path(tempfile.mkdtemp(prefix=f".{directory.name or 'output'}.", dir=parent))
            for name, data in files.items():
                fd = os.open(tmp / name, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
                with os.fdopen(fd, "wb") as f:
                    f.write(_bytes(data))
            os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; mkdir would give this
        with interrupts.committing():
            os.rename(tmp, directory)  # DIR appears now, complete
    except OSError as e:
        if tmp is None:  # DIR's parent directory takes no new entry
            raise _cannot_write(output, parent, e, False) from e
        raise InputError(f"{output}: cannot write ({e.strerror})") from e
    finally:  # an error, KeyboardInterrupt or SystemExit (SIGTERM) alike
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
