"""Ctrl-C (``SIGINT``) and ``SIGTERM`` end a run, whatever a library does with the exception.

Within :func:`handled` (the command line's run), a signal raises ``KeyboardInterrupt`` (Ctrl-C)
or ``SystemExit(128 + signal)`` (``SIGTERM``) where the program is, as Python does, and is also
recorded: a library that catches ``BaseException`` (trimesh does, around its optional imports,
which yourdfpy runs) cannot make it go away. :func:`check` raises it again before any output is
written, and :func:`exit_code` turns the run's exit code into ``128 + signal``.

A signal that comes while a module is being imported is not raised there: an import cut short
can leave a compiled extension half set up (and a later use of it crashing the interpreter),
and the library importing it may swallow the exception. It is delivered again every
:data:`RETRY` seconds until no import is under way, and raised then.

Outputs are put in place inside :func:`committing`: a signal recorded before it raises there,
before anything is replaced; during it, a signal is recorded and waits (the renames are short;
should one fail, the run ends with the signal's code); after it, the run has done its work, and
a signal no longer changes the exit code: an exit of 130 always means that no output was
changed.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator
from types import FrameType

__all__ = ["check", "committing", "exit_code", "handled", "held", "pending"]

SIGNALS = (signal.SIGINT, signal.SIGTERM)
RETRY = 0.05  # seconds between deliveries of a signal held off by an import
IMPORTING = ("<frozen importlib._bootstrap>", "<frozen importlib._bootstrap_external>")


class _State:
    active = False
    over = False  # the run has ended (and the program is ending): signals change nothing
    received: int | None = None  # the first signal of the run
    holding = False  # outputs are being put in place: a signal waits
    committed = False  # they are
    retrying = False  # a signal held off by an import will be delivered again


_state = _State()


def _raise(signum: int) -> None:
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise SystemExit(128 + signum)


def _importing(frame: FrameType | None) -> bool:
    """Whether ``frame`` (the one a signal interrupted) runs inside an import."""
    while frame is not None:
        if frame.f_code.co_filename in IMPORTING:
            return True
        frame = frame.f_back
    return False


def _deliver_again(signum: int) -> None:
    _state.retrying = False
    if _state.active and not _state.over:
        os.kill(os.getpid(), signum)


def _handler(signum: int, frame: FrameType | None) -> None:
    if _state.over:
        return
    if _state.received is None:
        _state.received = signum
    if _state.committed or _state.holding:
        return
    if _importing(frame):
        if not _state.retrying:
            _state.retrying = True
            timer = threading.Timer(RETRY, _deliver_again, (signum,))
            timer.daemon = True
            timer.start()
        return
    _raise(signum)


@contextlib.contextmanager
def handled(restore: bool = True) -> Iterator[None]:
    """Handle ``SIGINT`` and ``SIGTERM`` as the module docstring says, for the block (in the main
    thread only; elsewhere the block runs as it is and the caller handles its signals).

    ``restore``: put the previous handlers back after the block; a program that ends with the
    block keeps them instead, so that a signal between the run's end and the program's exit
    changes nothing (the run's outputs are complete).
    """
    if threading.current_thread() is not threading.main_thread() or _state.active:
        yield
        return
    previous = {s: signal.signal(s, _handler) for s in SIGNALS}
    _state.active, _state.received, _state.committed, _state.over = True, None, False, False
    _state.retrying = False
    try:
        yield
    finally:
        if restore:
            for s, handler in previous.items():
                signal.signal(s, handler)
        else:  # ignored, not handled: Python's finalization would reset a handler to the default
            _state.over = True
            for s in SIGNALS:
                signal.signal(s, signal.SIG_IGN)
        _state.active = False


def pending() -> bool:
    """Whether a signal came during the run, before its outputs were written."""
    return _state.active and _state.received is not None and not _state.committed


def check() -> None:
    """Raise the signal received during the run, if any (before writing an output)."""
    if pending() and _state.received is not None:
        _raise(_state.received)


@contextlib.contextmanager
def held() -> Iterator[None]:
    """A block no signal cuts short: one that comes is recorded, and :func:`check` (or the next
    one after the block) raises it. For steps that must not be cut between two statements, such
    as creating a temporary file and taking note of it."""
    if not _state.active:
        yield
        return
    previous = _state.holding
    _state.holding = True
    try:
        yield
    finally:
        _state.holding = previous


@contextlib.contextmanager
def committing() -> Iterator[None]:
    """The block that puts the run's outputs in place: a signal received before it raises here;
    one received while it runs is recorded and raises nothing (the renames are short); once it
    is done, the run's outputs are written."""
    if not _state.active:
        yield
        return
    check()
    with held():
        yield
        _state.committed = True


def exit_code(code: int) -> int:
    """The exit code of a run that would end with ``code``: ``128 + signal`` if a signal came
    before its outputs were written."""
    if pending() and _state.received is not None:
        return 128 + _state.received
    return code
