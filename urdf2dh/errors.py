"""One exception root for everything urdf2dh reports to a user.

Every failure the command line can meet is an :class:`Urdf2DhError`; the CLI prints its message
on one line (or a few) and exits with :attr:`Urdf2DhError.exit_code`. Library errors (lxml,
yourdfpy, Pinocchio, PyYAML) are wrapped with ``raise ... from e`` so that users read our message,
which names the file, link or joint at fault.

A message says what is wrong. Where an argument gets past the error, the error carries it as a
:class:`Remedy` naming the Python API's argument; the command line adds the matching option
(:data:`urdf2dh.cli.run.OPTIONS`).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

__all__ = [
    "MESSAGE_LENGTH",
    "ChainError",
    "ConversionError",
    "ExportError",
    "Implausible",
    "InputError",
    "NotConverged",
    "OracleError",
    "Remedy",
    "SourceError",
    "TableFileError",
    "Urdf2DhError",
    "UsageError",
    "choices",
    "missing",
    "near",
    "one_line",
    "shown",
    "visible",
]

SHOWN_LENGTH = 120  # characters of a name an error message shows
MESSAGE_LENGTH = 2000  # characters of an error line the command line prints, at most


@dataclass(frozen=True, slots=True)
class Remedy:
    """A way past an error: the argument ``argument`` of the Python API (``ignore_mimic``,
    ``tip``, ``xacro.timeout``), given ``value`` where it takes one; ``then`` says what to do,
    from its first character on (``"; choose one with {}"``), with ``{}`` where the argument (or
    the command line's option) goes: the command line prints it right after the message."""

    argument: str
    then: str
    value: str = ""

    def said(self, name: str) -> str:
        """``then`` with the argument called ``name`` (and its value)."""
        return self.then.replace("{}", f"{name} {self.value}" if self.value else name)


class Urdf2DhError(Exception):
    """Root of all urdf2dh errors. ``exit_code`` is what the CLI returns (2;
    docs/commands/index.md); ``remedy`` (or ``None``) the argument that gets past it, ``also``
    further ones, said after it."""

    exit_code = 2

    def __init__(
        self, *args: object, remedy: Remedy | None = None, also: tuple[Remedy, ...] = ()
    ) -> None:
        super().__init__(*args)
        self.remedy = remedy
        self.also = also


class UsageError(Urdf2DhError, ValueError):
    """A bad command-line option or option value, or a choice the Python API does not know (a
    convention, style, format or export target name); a ``ValueError`` too."""


class InputError(Urdf2DhError):
    """A file or model that cannot be used (missing, malformed, inconsistent)."""


class SourceError(InputError):
    """SOURCE is neither a file nor a bundled robot name."""


class ChainError(InputError):
    """No usable serial chain between the requested base and tip links."""


class TableFileError(InputError):
    """A table file (docs/formats/table-file.md) that is malformed or contradicts itself."""


class ExportError(InputError):
    """A chain that an export target cannot carry; the message names the target and says why."""


class Implausible(Urdf2DhError):
    """A calibration the measurements contradict (exit 3; nothing is written): a file read
    with the wrong units or orders, a noise level the residuals refute, a model that misses
    what the measurements show. ``causes`` names each finding (``length-unit``,
    ``joint-degrees``, ``noise-under-stated``, ...: :data:`urdf2dh.calibration.plausible.KINDS`);
    ``result`` is the rejected calibration, where there is one (``accept=True`` returns it with
    the findings among its warnings)."""

    exit_code = 3

    def __init__(
        self,
        *args: object,
        causes: tuple[str, ...] = (),
        result: object | None = None,
        remedy: Remedy | None = None,
        also: tuple[Remedy, ...] = (),
    ) -> None:
        super().__init__(*args, remedy=remedy, also=also)
        self.causes = causes
        self.result = result


class NotConverged(Urdf2DhError):
    """A calibration's identification did not converge (exit 1; nothing is written)."""

    exit_code = 1


class OracleError(InputError):
    """An oracle (``pinocchio``, ``mujoco``) that cannot judge a chain: ``oracle`` names it, the
    message says why."""

    def __init__(self, oracle: str, message: str, remedy: Remedy | None = None) -> None:
        super().__init__(message, remedy=remedy)
        self.oracle = oracle


class ConversionError(Urdf2DhError):
    """The conversion cannot produce a table that meets its own exactness check."""

    exit_code = 1


def choices(names: Iterable[str], limit: int = 12, quoted: bool = False) -> str:
    """Format a list of valid names for an error message: ``[a, b, c, ... (20 in all)]``, each
    as :func:`visible` shows it (``quoted``: as :func:`shown` does, for names from a file)."""
    items = [(shown if quoted else visible)(n) for n in sorted(names)]
    listed = ", ".join(items[:limit])
    if len(items) > limit:
        listed += f", ... ({len(items)} in all)"
    return f"[{listed}]"


def near(word: str, names: Iterable[str], quoted: bool = True) -> str:
    """``" (did you mean 'x'?)"`` naming the valid name closest to a misspelled ``word`` (by
    :func:`difflib.get_close_matches`, case ignored; names as close as it, up to three), or
    ``""`` when none is close. Names are shown as :func:`shown` does (``quoted``) or as
    :func:`visible` does."""
    import difflib

    by_folded: dict[str, str] = {}
    for name in names:
        by_folded.setdefault(name.casefold(), name)
    folded = word.casefold()
    close = difflib.get_close_matches(folded, by_folded, n=3, cutoff=0.6)
    if not close:
        return ""
    score = difflib.SequenceMatcher(None, folded, close[0]).ratio()
    close = [c for c in close if difflib.SequenceMatcher(None, folded, c).ratio() == score]
    show = shown if quoted else visible
    listed = " or ".join(show(by_folded[c]) for c in close)
    return f" (did you mean {listed}?)"


def visible(text: str) -> str:
    """``text`` on one line, as Python's ``repr`` shows it without the quotes: backslash
    doubled, and every character Python does not print (line breaks, U+2028/U+2029/U+0085,
    controls such as ESC, format characters such as the bidi overrides, surrogates) as its
    Python escape. Other characters, non-ASCII letters included, are kept.

    How names from files appear in comments of generated files and in text for people."""
    if text.isprintable() and "\\" not in text:
        return text
    return "".join(_escape_char(ch) for ch in text)


def _escape_char(ch: str) -> str:
    return "\\\\" if ch == "\\" else ch if ch.isprintable() else _escape(ch)


def _escape(ch: str) -> str:
    """An unprintable character as Python writes it in a string literal (``\\n``, ``\\x1b``)."""
    return repr(ch)[1:-1]


def shown(name: object) -> str:
    """A name (or any value) from a file as a message shows it: Python's ``repr`` (quoted, with
    escapes for line breaks, controls and every other unprintable character, so the message
    stays one line and shows what the name holds), cut after :data:`SHOWN_LENGTH` characters
    with the full length said. The one rule for everything from an input that a message
    names."""
    if not isinstance(name, str):
        text = repr(name)
        return (
            text
            if len(text) <= SHOWN_LENGTH
            else f"{text[:SHOWN_LENGTH]}... ({len(text)} characters)"
        )
    if len(name) <= SHOWN_LENGTH:
        return repr(name)
    return f"{name[:SHOWN_LENGTH]!r}... ({len(name)} characters)"


def one_line(text: str) -> str:
    """A message as the command line prints it: line breaks and other characters Python does
    not print written as their escapes (backslashes kept as they are: the names in a message
    are escaped already, :func:`shown`), so that it stays one line, and at most
    :data:`MESSAGE_LENGTH` characters, its middle cut out beyond (the last guard against a
    library's message quoting a whole input)."""
    line = "".join(c if c.isprintable() else _escape(c) for c in text)
    if len(line) <= MESSAGE_LENGTH:
        return line
    keep = MESSAGE_LENGTH // 2
    return f"{line[:keep]} ... ({len(line):,} characters) ... {line[-keep:]}"


def missing(what: str, package: str, extra: str | None = None) -> InputError:
    """The error for an optional dependency that is not installed: what needs it (``"the
    picture"``) and how to install it (``extra``: urdf2dh's optional dependency that brings it)."""
    also = f" (or pip install 'urdf2dh[{extra}]')" if extra else ""
    return InputError(f"{what} needs {package}; install it with: pip install {package}{also}")
