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

__all__ = ["Finished", "Overflow", "TimedOut", "run"]

CHUNK = 65536


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
    proc = subprocess.Popen(
        list(argv),
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=dict(env),
        start_new_session=True,
    )
    try:
        assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
        try:
            proc.stdin.write(stdin)
            proc.stdin.close()
        except BrokenPipeError:  # it ended without reading: its status says why
            pass
        out, err = _read(proc, deadline, stdout_limit, stderr_limit, tail)
        _wait_unreaped(proc, deadline)
        _kill_group(proc)
        return Finished(proc.wait(), out, err)
    finally:
        if proc.returncode is None:  # not reaped yet: its pid is still the group's id
            _kill_group(proc)
            proc.wait()
        for stream in (proc.stdin, proc.stdout, proc.stderr):
            if stream is not None:
                stream.close()


def _read(
    proc: subprocess.Popen[bytes], deadline: float, stdout_limit: int, stderr_limit: int, tail: int
) -> tuple[bytes, bytes]:
    """Both outputs, read as they come until both are closed."""
    assert proc.stdout is not None and proc.stderr is not None
    out = bytearray()
    err = bytearray()
    err_total = 0
    with selectors.DefaultSelector() as selector:
        selector.register(proc.stdout, selectors.EVENT_READ, "stdout")
        selector.register(proc.stderr, selectors.EVENT_READ, "stderr")
        while selector.get_map():
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimedOut()
            for key, _ in selector.select(remaining):
                chunk = os.read(key.fd, CHUNK)
                if not chunk:
                    selector.unregister(key.fileobj)
                elif key.data == "stdout":
                    out += chunk
                    if len(out) > stdout_limit:
                        raise Overflow("stdout", stdout_limit)
                else:
                    err_total += len(chunk)
                    err += chunk
                    del err[:-tail]
                    if err_total > stderr_limit:
                        raise Overflow("stderr", stderr_limit)
    return bytes(out), bytes(err)


def _wait_unreaped(proc: subprocess.Popen[bytes], deadline: float) -> None:
    """Wait for the child's end without reaping it, so that its process group id cannot be
    taken by another process before the group is killed."""
    waitid = getattr(os, "waitid", None)
    while True:
        if waitid is None:  # no waitid (macOS): reap, then kill what is left of the group
            try:
                proc.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                raise TimedOut() from None
            return
        try:
            if waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT | os.WNOHANG) is not None:
                return
        except ChildProcessError:  # reaped already (SIGCHLD ignored): nothing to wait for
            return
        if time.monotonic() >= deadline:
            raise TimedOut()
        time.sleep(0.005)


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
