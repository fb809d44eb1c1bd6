"""MATLAB scripts read the way MATLAB reads them, for the tests: tokens, comments, statements.

Written from MathWorks' language documentation, for the subset our exports write and strictly
(anything else raises :class:`MatlabSyntaxError`, so a generated file that MATLAB would read
differently fails the test):

* ``%`` starts a comment outside a literal; ``%{`` / ``%}`` alone on a line open and close a
  block comment (nested); ``...`` continues the statement on the next line (the rest of the
  line is a comment);
* ``"..."`` is a string (``""`` inside is one ``"``), ``'...'`` a char vector (``''`` is one
  ``'``), except that ``'`` right after a name, number, closing bracket or another transpose is
  the transpose operator; a literal cannot span lines;
* ``!`` at the start of a statement runs the rest of the line in the shell;
* statements end at a line break (LF, CR) or at ``;`` / ``,`` outside brackets.

Expressions are evaluated as far as our scripts need: numbers, ``pi`` (MATLAB's function: the
float64 nearest pi), unary minus (binding tighter than ``*`` and ``/``, as in MATLAB), ``*`` and
``/`` of numbers, matrices ``[1 2; 3 4]`` (whose elements may be products: ``[0 -pi/2]``),
``char([10 13])`` (UTF-16 code units), ``+`` of a string and a string or char vector (a string),
``[...]`` of char vectors (a char vector), names, ``a.b`` fields and calls.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "Call",
    "Chars",
    "MatlabScript",
    "MatlabSyntaxError",
    "Ref",
    "Statement",
    "Str",
    "read_matlab",
]


class MatlabSyntaxError(AssertionError):
    """The script is not MATLAB as our exports write it."""


@dataclass(frozen=True)
class Str:
    """A MATLAB string scalar."""

    value: str


@dataclass(frozen=True)
class Chars:
    """A MATLAB char vector."""

    value: str


@dataclass(frozen=True)
class Ref:
    """A name or field read (``robot``, ``body.Name``)."""

    name: str


@dataclass(frozen=True)
class Call:
    """A function call with evaluated arguments."""

    name: str
    args: tuple[Any, ...]


@dataclass(frozen=True)
class Statement:
    """``target = value`` (``target`` None for a bare expression, such as a call)."""

    target: str | None
    value: Any
    line: int


@dataclass
class MatlabScript:
    statements: list[Statement] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)  # text after % (or ...), in file order


@dataclass(frozen=True)
class _Token:
    kind: str  # name, number, str, chars, op, end, shell
    text: str
    space_before: bool
    line: int


_NUMBER = re.compile(r"(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_NAME = re.compile(r"[A-Za-z]\w*")
_OPERATORS = ("==", "~=", "<=", ">=", ".*", "./", ".^", ".'", *"+-*/\\^()[]{},;=.:<>&|~@")
_TRANSPOSE_AFTER = ("name", "number")


def _lines(text: str) -> list[str]:
    return re.split(r"\r\n|\r|\n", text)


def _lex(text: str) -> tuple[list[_Token], list[str]]:
    tokens: list[_Token] = []
    comments: list[str] = []
    block = 0
    depth = 0
    for number, line in enumerate(_lines(text), 1):
        if line.strip() == "%{":
            block += 1
            continue
        if block:
            if line.strip() == "%}":
                block -= 1
            else:
                comments.append(line)
            continue
        i, space = 0, True
        at_start = depth == 0 and (
            not tokens or tokens[-1].kind == "end" or tokens[-1].text in (";", ",")
        )
        if at_start and line.lstrip().startswith("!"):
            tokens.append(_Token("shell", line.lstrip()[1:], True, number))
            tokens.append(_Token("end", "\n", False, number))
            continue
        continued = False
        while i < len(line):
            ch = line[i]
            if ch in " \t":
                i, space = i + 1, True
                continue
            if ch == "%":
                comments.append(line[i + 1 :])
                break
            if line.startswith("...", i):
                comments.append(line[i + 3 :])
                continued = True
                break
            prev = tokens[-1] if tokens and tokens[-1].line == number else None
            transpose = (
                ch == "'"
                and prev is not None
                and not space
                and (prev.kind in _TRANSPOSE_AFTER or prev.text in (")", "]", "}", "'", ".'"))
            )
            if ch in "'\"" and not transpose:
                end = i + 1
                while True:
                    end = line.find(ch, end)
                    if end < 0:
                        raise MatlabSyntaxError(f"line {number}: unterminated literal: {line!r}")
                    if line.startswith(ch * 2, end):
                        end += 2
                        continue
                    break
                body = line[i + 1 : end].replace(ch * 2, ch)
                tokens.append(_Token("str" if ch == '"' else "chars", body, space, number))
                i, space = end + 1, False
                continue
            if m := _NUMBER.match(line, i):
                tokens.append(_Token("number", m[0], space, number))
            elif m := _NAME.match(line, i):
                tokens.append(_Token("name", m[0], space, number))
            else:
                op = next((o for o in _OPERATORS if line.startswith(o, i)), None)
                if op is None:
                    raise MatlabSyntaxError(f"line {number}: unexpected {ch!r}: {line!r}")
                depth += op in "([{"
                depth -= op in ")]}"
                tokens.append(_Token("op", op, space, number))
                i += len(op)
                space = False
                continue
            i += len(m[0])
            space = False
        if not continued:
            tokens.append(_Token("end", "\n", False, number))
    if block:
        raise MatlabSyntaxError("unterminated block comment")
    return tokens, comments


def _statements(tokens: list[_Token]) -> list[list[_Token]]:
    out: list[list[_Token]] = [[]]
    depth = 0
    for t in tokens:
        if t.kind == "op" and t.text in "([{":
            depth += 1
        elif t.kind == "op" and t.text in ")]}":
            depth -= 1
        if t.kind == "end" or (depth == 0 and t.kind == "op" and t.text in (";", ",")):
            if depth and t.kind == "end":
                raise MatlabSyntaxError(f"line {t.line}: bracket left open")
            out.append([])
        else:
            out[-1].append(t)
    return [s for s in out if s]


class _Parser:
    def __init__(self, tokens: list[_Token]) -> None:
        self.tokens, self.i = tokens, 0

    def peek(self, text: str | None = None) -> _Token | None:
        t = self.tokens[self.i] if self.i < len(self.tokens) else None
        if t is None or (text is not None and (t.kind != "op" or t.text != text)):
            return None
        return t

    def take(self, text: str | None = None) -> _Token:
        t = self.peek(text) if text is not None else self.peek()
        if t is None:
            raise MatlabSyntaxError(f"expected {text or 'more'}, got {t.text if t else 'end'}")
        self.i += 1
        return t

    def expression(self) -> Any:
        value = self.term()
        while self.peek("+") or self.peek("-"):
            op = self.take().text
            value = _plus(value, self.term()) if op == "+" else _minus(value, self.term())
        return value

    def term(self) -> Any:
        value = self.unary()
        while self.peek("*") or self.peek("/"):
            op = self.take().text
            right = self.unary()
            if not isinstance(value, float) or not isinstance(right, float):
                raise MatlabSyntaxError(f"{value!r} {op} {right!r}")
            value = value * right if op == "*" else value / right
        return value

    def unary(self) -> Any:
        if self.peek("-"):
            self.take()
            value = self.unary()
            if not isinstance(value, float | np.ndarray):
                raise MatlabSyntaxError(f"unary minus of {value!r}")
            return -value
        return self.primary()

    def primary(self) -> Any:
        t = self.take()
        if t.kind == "number":
            return float(t.text)
        if t.kind == "str":
            return Str(t.text)
        if t.kind == "chars":
            return Chars(t.text)
        if t.kind == "op" and t.text == "[":
            return self.matrix()
        if t.kind == "op" and t.text == "(":
            value = self.expression()
            self.take(")")
            return value
        if t.kind != "name":
            raise MatlabSyntaxError(f"line {t.line}: unexpected {t.text!r}")
        name = t.text
        while (
            self.peek(".")
            and self.i + 1 < len(self.tokens)
            and self.tokens[self.i + 1].kind == "name"
        ):
            self.take()
            name += "." + self.take().text
        if self.peek("("):
            self.take()
            args = []
            while not self.peek(")"):
                args.append(self.expression())
                if not self.peek(")"):
                    self.take(",")
            self.take(")")
            if name == "char":
                return _char(args)
            return Call(name, tuple(args))
        if name == "pi":
            return math.pi
        return Ref(name)

    def matrix(self) -> Any:
        rows: list[list[Any]] = [[]]
        while not self.peek("]"):
            if self.peek(";"):
                self.take()
                rows.append([])
                continue
            if self.peek(","):
                self.take()
                continue
            rows[-1].append(self.term())  # inside brackets, whitespace separates elements
        self.take("]")
        items = [x for row in rows for x in row]
        if items and all(isinstance(x, Chars) for x in items) and len(rows) == 1:
            return Chars("".join(x.value for x in items))
        if not all(isinstance(x, float) for x in items):
            raise MatlabSyntaxError(f"matrix of {items!r}")
        return np.array(rows if len(rows) > 1 else rows[0], dtype=float)


def _char(args: list[Any]) -> Chars:
    if len(args) != 1:
        raise MatlabSyntaxError(f"char({args!r})")
    units = np.atleast_1d(args[0])
    if not all(float(u).is_integer() and 0 <= u <= 0xFFFF for u in units):
        raise MatlabSyntaxError(f"char({args[0]!r})")
    data = b"".join(int(u).to_bytes(2, "little") for u in units)
    return Chars(data.decode("utf-16-le", "surrogatepass"))


def _plus(a: Any, b: Any) -> Any:
    if isinstance(a, Str) or isinstance(b, Str):
        if not all(isinstance(x, Str | Chars) for x in (a, b)):
            raise MatlabSyntaxError(f"{a!r} + {b!r}")
        return Str(a.value + b.value)
    if isinstance(a, float) and isinstance(b, float):
        return a + b
    raise MatlabSyntaxError(f"{a!r} + {b!r} (char + char is numeric)")


def _minus(a: Any, b: Any) -> Any:
    if isinstance(a, float) and isinstance(b, float):
        return a - b
    raise MatlabSyntaxError(f"{a!r} - {b!r}")


def _statement(tokens: list[_Token]) -> Statement:
    if tokens[0].kind == "shell":
        return Statement("!", tokens[0].text, tokens[0].line)
    p = _Parser(tokens)
    target = None
    eq = next((k for k, t in enumerate(tokens) if t.text == "=" and t.kind == "op"), None)
    if eq is not None:
        target = "".join(t.text for t in tokens[:eq])
        if not re.fullmatch(r"[A-Za-z]\w*(\.[A-Za-z]\w*|\(\d+\))?", target):
            raise MatlabSyntaxError(f"line {tokens[0].line}: cannot assign to {target!r}")
        p.i = eq + 1
    value = p.expression()
    if p.peek() is not None:
        raise MatlabSyntaxError(f"line {tokens[0].line}: trailing {p.peek().text!r}")  # type: ignore[union-attr]
    return Statement(target, value, tokens[0].line)


def read_matlab(text: str) -> MatlabScript:
    """The statements (evaluated) and comments of a MATLAB script."""
    tokens, comments = _lex(text)
    return MatlabScript([_statement(s) for s in _statements(tokens)], comments)
