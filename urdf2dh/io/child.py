"""Run a child process that must not outlive its run, read its output within bounds.

:func:`run` starts the child in a session (and so a process group) of its own with the
environment it is given, writes its standard input, and reads its standard output and error at
once, each up to a limit, until it ends or its time is up. On every way out (the child's end, a
limit, the time, Ctrl-C or ``SIGTERM`` in urdf2dh, an exception) the whole process group is killed
with ``SIGKILL`` before the child is reaped, so that nothing the child started in its group is
left running; a child that set up a session of its own is the child's own confinement's to
prevent (``docs/security.md``).
"""

from __future__ import annotations

import os
import selectors
import signal
import subprocess
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from .interrupts import check, held

__all__ = ["Finished", "Overflow", "TimedOut", "run"]

CHUNK = 65536
POLL = 0.02  # seconds between looks at whether the child has ended
DRAIN = 0.05  # seconds to wait for more output once the child's group is dead


@dataclass(frozen=True, slots=True)
class Finished:
    """A child that ended: its exit status (negative: killed by that signal), its standard output,
    and the last bytes of its standard error."""

    returncode: int
    stdout: bytes
    stderr_tail: bytes


class TimedOut(Exception):
    """The child ran longer than its time."""


class Overflow(Exception):
    """The child wrote more than its limit on one of its outputs."""

    def __init__(self, stream: str, limit: int) -> None:
        super().__init__(f"more than {limit} bytes on {stream}")
        self.stream, self.limit = stream, limit


def run(
    argv: Sequence[str],
    stdin: bytes,
    env: Mapping[str, str],
    timeout: float,
    stdout_limit: int,
    stderr_limit: int,
    tail: int = 4096,
) -> Finished:
    """Run ``argv`` to its end within ``timeout`` seconds (see the module docstring).

    Raises
    ------
    TimedOut
        It was still running after ``timeout`` seconds.
    Overflow
        It wrote more than ``stdout_limit`` bytes on its standard output, or ``stderr_limit`` on
        its standard error (of which only the last ``tail`` bytes are kept).
    """
    deadline = time.monotonic() + timeout
    with held():  # Ctrl-C now would leave the child unknown to the clean-up below
        proc = subprocess.Popen(
            list(argv),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env=dict(env),
            start_new_session=True,
        )
    try:
        check()
        assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
        try:
            proc.stdin.write(stdin)
            proc.stdin.close()
        except BrokenPipeError:  # it ended without reading: its status says why
            pass
        out, err = _read(proc, deadline, stdout_limit, stderr_limit, tail)
        return Finished(proc.wait(), out, err)
    finally:
        if proc.returncode is None:  # not reaped yet: its pid is still the group's id
            _kill_group(proc)
            proc.wait()
        for stream in (proc.stdin, proc.stdout, proc.stderr):
            if stream is not None:
                stream.close()


class _Outputs:
    """What the child wrote, within the limits."""

    def __init__(self, stdout_limit: int, stderr_limit: int, tail: int) -> None:
        self.out, self.err, self.err_total = bytearray(), bytearray(), 0
        self.stdout_limit, self.stderr_limit, self.tail = stdout_limit, stderr_limit, tail

    def add(self, stream: str, chunk: bytes) -> None:
        if stream == "stdout":
            self.out += chunk
            if len(self.out) > self.stdout_limit:
                raise Overflow("stdout", self.stdout_limit)
        else:
            self.err_total += len(chunk)
            self.err += chunk
            del self.err[: -self.tail]
            if self.err_total > self.stderr_limit:
                raise Overflow("stderr", self.stderr_limit)


def _read(
    proc: subprocess.Popen[bytes], deadline: float, stdout_limit: int, stderr_limit: int, tail: int
) -> tuple[bytes, bytes]:
    """Both outputs, read as they come until the child ends; then its group is killed (before
    the child is reaped) and what is left in the pipes read."""
    assert proc.stdout is not None and proc.stderr is not None
    outputs = _Outputs(stdout_limit, stderr_limit, tail)
    ended = False
    with selectors.DefaultSelector() as selector:
        selector.register(proc.stdout, selectors.EVENT_READ, "stdout")
        selector.register(proc.stderr, selectors.EVENT_READ, "stderr")
        while len(selector.get_map()) > 0:
            if not ended and _ended(proc):
                _kill_group(proc)  # whatever it started dies now, holding the pipes or not
                ended = True
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimedOut()
            ready = selector.select(min(remaining, POLL) if not ended else DRAIN)
            if ended and not ready:  # its group is dead: all it wrote has been read
                break
            for key, _ in ready:
                chunk = os.read(key.fd, CHUNK)
                if chunk:
                    outputs.add(key.data, chunk)
                else:
                    selector.unregister(key.fileobj)
    if not ended:  # both pipes closed before it ended
        _wait_unreaped(proc, deadline)
        _kill_group(proc)
    return bytes(outputs.out), bytes(outputs.err)


def _ended(proc: subprocess.Popen[bytes]) -> bool:
    """Whether the child has ended, without reaping it (its pid stays the group's id)."""
    waitid = getattr(os, "waitid", None)
    if waitid is None:  # no waitid (macOS): the pipes' end tells
        return False
    try:
        return waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT | os.WNOHANG) is not None
    except ChildProcessError:  # reaped already (SIGCHLD ignored)
        return True


def _wait_unreaped(proc: subprocess.Popen[bytes], deadline: float) -> None:
    """Wait for the child's end (without reaping it where the system allows)."""
    while not _ended(proc):
        if getattr(os, "waitid", None) is None:
            try:
                proc.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                raise TimedOut() from None
            return
        if time.monotonic() >= deadline:
            raise TimedOut()
        time.sleep(POLL)


def _kill_group(proc: subprocess.Popen[bytes]) -> None:
    """``SIGKILL`` to every process of the child's group (its pid, the group's id)."""
    killpg = getattr(os, "killpg", None)
    if killpg is None:  # not POSIX
        proc.kill()
        return
    try:
        killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):  # the group is gone already
        pass
