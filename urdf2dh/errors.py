"""One exception root for everything urdf2dh reports to a user.

Every failure the command line can meet is an :class:`Urdf2DhError`; the CLI prints its message
on one line (or a few) and exits with :attr:`Urdf2DhError.exit_code`. Library errors (lxml,
yourdfpy, Pinocchio, PyYAML) are wrapped with ``raise ... from e`` so that users read our message,
which names the file, link or joint at fault.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "ChainError",
    "ConversionError",
    "ExportError",
    "InputError",
    "SourceError",
    "TableFileError",
    "Urdf2DhError",
    "UsageError",
    "VerificationError",
    "choices",
]


class Urdf2DhError(Exception):
    """Root of all urdf2dh errors. ``exit_code`` is what the CLI returns (SPEC §1)."""

    exit_code = 2


class UsageError(Urdf2DhError):
    """A bad command-line option or option value."""


class InputError(Urdf2DhError):
    """A file or model that cannot be used (missing, malformed, inconsistent)."""


class SourceError(InputError):
    """SOURCE is neither a file nor a bundled robot name."""


class ChainError(InputError):
    """No usable serial chain between the requested base and tip links."""


class TableFileError(InputError):
    """A table file (SPEC §2) that is malformed or contradicts itself."""


class ExportError(InputError):
    """A chain that an export target cannot carry; the message names the target and says why."""


class ConversionError(Urdf2DhError):
    """The conversion cannot produce a table that meets its own exactness check."""

    exit_code = 1


class VerificationError(Urdf2DhError):
    """``verify`` found a forward-kinematics error beyond tolerance."""

    exit_code = 1


def choices(names: Iterable[str], limit: int = 12) -> str:
    """Format a list of valid names for an error message: ``[a, b, c, ... (20 in all)]``."""
    items = sorted(names)
    shown = ", ".join(items[:limit])
    if len(items) > limit:
        shown += f", ... ({len(items)} in all)"
    return f"[{shown}]"
