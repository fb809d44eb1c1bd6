"""HAL files read the way LinuxCNC's halcmd reads them (``halcmd -f FILE``), for the tests.

From halcmd's source (``halcmd_main.c``, ``halcmd.c``): the file is read with
``fgets(buf, MAX_CMD_LEN, file)`` and ``MAX_CMD_LEN`` = 1024, so a line of more than 1023 bytes
is read as several lines; each is cut at the first ``#`` outside single or double quotes (a
quote left open is an error), then split into tokens at whitespace (quotes group); a carriage
return other than before the line's end is an error. Every line with a token is a command.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["FGETS_BYTES", "HalFile", "HalSyntaxError", "read_hal"]

FGETS_BYTES = 1024 - 1  # fgets reads at most MAX_CMD_LEN - 1 bytes, the newline included


class HalSyntaxError(AssertionError):
    """A line halcmd would reject."""


@dataclass
class HalFile:
    commands: list[list[str]] = field(default_factory=list)  # live lines, as tokens
    comments: list[str] = field(default_factory=list)  # the text after each '#'


def _fgets(data: bytes) -> list[bytes]:
    out: list[bytes] = []
    for line in data.splitlines(keepends=True):
        while len(line) > FGETS_BYTES:
            out.append(line[:FGETS_BYTES])
            line = line[FGETS_BYTES:]
        out.append(line)
    return out


def _strip_comment(line: bytes) -> tuple[bytes, bytes | None]:
    quote = None
    for i, c in enumerate(line):
        ch = bytes([c])
        if quote is None and ch in (b"#", b"\n"):
            return line[:i], (line[i + 1 :].rstrip(b"\n") if ch == b"#" else None)
        if quote is None and ch in (b"'", b'"'):
            quote = ch
        elif ch == quote:
            quote = None
        elif quote is not None and ch == b"\n":
            raise HalSyntaxError(f"unterminated quoted string: {line!r}")
    if quote is not None:
        raise HalSyntaxError(f"unterminated quoted string: {line!r}")
    return line, None


def _tokens(line: bytes) -> list[str]:
    if b"\r" in line.rstrip(b"\r"):
        raise HalSyntaxError(f"embedded carriage return: {line!r}")
    tokens: list[bytes] = []
    current: bytes | None = None
    quote = None
    for c in line.rstrip(b"\r"):
        ch = bytes([c])
        if quote is not None:
            current = (current or b"") + ch if ch != quote else current
            quote = None if ch == quote else quote
        elif ch in (b"'", b'"'):
            quote, current = ch, current or b""
        elif ch.isspace():
            if current is not None:
                tokens.append(current)
            current = None
        else:
            current = (current or b"") + ch
    if current is not None:
        tokens.append(current)
    return [t.decode("utf-8", "replace") for t in tokens]


def read_hal(text: str) -> HalFile:
    """The live commands and the comments of a HAL file, as halcmd sees them."""
    out = HalFile()
    for line in _fgets(text.encode("utf-8")):
        live, comment = _strip_comment(line)
        if comment is not None:
            out.comments.append(comment.decode("utf-8", "replace"))
        tokens = _tokens(live)
        if tokens:
            out.commands.append(tokens)
    return out
