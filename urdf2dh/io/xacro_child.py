"""The xacro expansion process (``docs/security.md``): run as a script by :mod:`urdf2dh.io.xacro`,
``python -I -S -B -X utf8 xacro_child.py``, so that nothing from the working directory,
``PYTHONPATH`` or the user's site-packages can be imported.

It reads a job (JSON) on stdin, confines itself (:mod:`.confine`), expands the file and writes on
stdout one line of JSON, then, on success, the URDF text:

* ``{"read": [FILE, ...], "landlock": ABI}`` and the URDF: every file the expansion opened, and
  the Landlock ABI version that confined its reading (0: none, the kernel has no Landlock);
* ``{"error": KIND, "message": TEXT, ...}``: KIND is ``refused`` (an expression the strict
  evaluation refuses; with ``file`` and ``expression``), ``unreadable`` (a file outside what
  the expansion may read; with ``file``, and ``withheld``: the SOURCE's directory when that was
  not read for being a broad one, else empty), ``package`` (a ROS package not given; with
  ``package``), ``no-xacro`` (the xacro package is not installed), ``confine`` (Landlock is
  there but refused the rules) or ``xacro`` (anything xacro reports).

What the expansion may read (:func:`readable`): beneath the SOURCE's directory and each
package's directory, and the SOURCE itself, symbolic links resolved as the kernel resolves them.
Every file xacro opens (an include, ``xacro.load_yaml``) and every directory an include's glob
pattern lists is checked against that first (:func:`_reads`); Landlock
(:func:`.confine.restrict_reading`), where the kernel has it, then makes the kernel refuse any
other read, the directories of the modules already loaded excepted (the interpreter's lazy
imports of ``encodings``).

Exit status 3 means out of memory. Only the standard library is imported before the job gives
the directories of ``xacro`` and ``yaml``.

The strict evaluation (:func:`refusal`) refuses, in every ``${...}`` and ``$(eval ...)``
expression and before xacro evaluates it, what lets an expression reach beyond the values it is
given (xacro itself refuses names starting with ``__`` at the top level only): lambdas,
generator expressions, assignment expressions, names starting with ``__``, attributes starting
with ``_``, and ``format``/``format_map`` other than on a string literal whose fields read no
attribute. ``python.type`` and ``python.vars`` are refused when called, and ``$(eval ...)`` sees
only the builtins xacro's ``python`` namespace offers.
"""

from __future__ import annotations

import ast
import builtins
import contextlib
import json
import os
import re
import string
import sys
import types
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path
from types import ModuleType
from typing import Any

__all__ = [
    "FORMATTING",
    "OUT_OF_MEMORY",
    "PACKAGE_URL",
    "REFUSED_CALLS",
    "REFUSED_SYNTAX",
    "SHOWN_EXPRESSION",
    "PackageMissing",
    "ReadRefused",
    "RefusedExpression",
    "expand",
    "main",
    "may_read",
    "readable",
    "refusal",
]

OUT_OF_MEMORY = 3
PACKAGE_URL = "package://"
GLOB_MAGIC = re.compile("[*?[]")  # what makes an include's file name a glob pattern
SHOWN_EXPRESSION = 120  # characters of a refused expression shown in the message
REFUSED_SYNTAX = {
    ast.Lambda: "a lambda",
    ast.GeneratorExp: "a generator expression",
    ast.NamedExpr: "an assignment expression (:=)",
    ast.Await: "await",
    ast.Yield: "yield",
    ast.YieldFrom: "yield from",
}
FORMATTING = ("format", "format_map")
REFUSED_CALLS = {  # xacro's python namespace: -> why calling it is refused
    "type": "it hands out any value's class",
    "vars": "it hands out any object's attributes, private ones included",
}


class RefusedExpression(Exception):
    """An expression the strict evaluation refuses."""

    def __init__(self, file: str | None, expression: str, why: str) -> None:
        super().__init__(why)
        self.file, self.expression, self.why = file, expression, why


class ReadRefused(Exception):
    """A file (or a directory to list) outside what the expansion may read; ``withheld``: the
    SOURCE's own directory when that is not read for being a broad one (:func:`readable`)."""

    def __init__(self, file: str, withheld: str | None) -> None:
        super().__init__(file)
        self.file, self.withheld = file, withheld


class PackageMissing(Exception):
    """``$(find NAME)`` or ``package://NAME`` for a package not given."""

    def __init__(self, package: str) -> None:
        super().__init__(package)
        self.package = package


# --------------------------------------------------------------------------- strict evaluation


def refusal(expression: str) -> str | None:
    """Why the strict evaluation refuses ``expression`` (a Python expression), or ``None``.

    Text that is not an expression is left to xacro, which reports the syntax error.
    """
    try:
        tree = ast.parse(expression.strip(), mode="eval")
    except (SyntaxError, ValueError):
        return None
    except (RecursionError, MemoryError):
        return "it is nested too deeply"
    on_literal = {
        id(node.func)
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr in FORMATTING
        and isinstance(node.func.value, ast.Constant)
        and isinstance(node.func.value.value, str)
    }
    for node in ast.walk(tree):
        syntax = REFUSED_SYNTAX.get(type(node))
        if syntax is not None:
            return f"{syntax} is not allowed"
        if isinstance(node, ast.Name) and node.id.startswith("__"):
            return f"the name '{node.id}' is not allowed"
        if isinstance(node, ast.Attribute):
            if node.attr.startswith("_"):
                return f"the attribute '.{node.attr}' is not allowed"
            if node.attr in FORMATTING:
                if id(node) not in on_literal:
                    return f"'.{node.attr}()' is allowed on a string literal only"
                field = _attribute_field(node.value.value)  # type: ignore[attr-defined]
                if field is not None:
                    return f"the format field '{{{field}}}' reads an attribute"
    return None


def _attribute_field(template: str) -> str | None:
    """The first replacement field of a format string that reads an attribute (``{0.x}``)."""
    try:
        parsed = list(string.Formatter().parse(template))
    except ValueError:  # a malformed template: str.format refuses it itself
        return None
    for _, field, spec, _ in parsed:
        if field is not None and "." in field:
            return field
        inner = _attribute_field(spec) if spec else None
        if inner is not None:
            return inner
    return None


def _strict(xacro: ModuleType, subst: ModuleType) -> None:
    """Check every expression before xacro evaluates it (``${...}``, YAML unit tags and
    ``$(eval ...)``), and take away what :data:`REFUSED_CALLS` names."""
    evaluate = xacro.safe_eval

    def checked(expression: Any, symbols: Any, local: Any = None) -> Any:
        if isinstance(expression, str):
            why = refusal(expression)
            if why is not None:
                stack = getattr(xacro, "filestack", None) or [None]
                raise RefusedExpression(stack[-1], expression, why)
        return evaluate(expression, symbols, local)

    xacro.safe_eval = checked  # type: ignore[attr-defined] # looked up by name at each use (eval_text, YAML unit tags)
    namespace = xacro._global_symbols["python"]
    for name, why in REFUSED_CALLS.items():
        dict.__setitem__(namespace, name, _refused_call(name, why))
    allowed = {k: v for k, v in namespace.items() if k not in REFUSED_CALLS}

    def restricted_eval(source: str, _globals: Any, local: Any) -> Any:
        why = refusal(source)
        if why is not None:
            raise RefusedExpression(getattr(xacro, "filestack", [None])[-1], source, why)
        return builtins.eval(source, {"__builtins__": {**allowed, "None": None}}, local)

    # substitution_args._eval calls eval(s, {}, ...), which would hand it every builtin; a
    # module-level name `eval` is found before the builtin one
    subst.eval = restricted_eval  # type: ignore[attr-defined]


def _refused_call(name: str, why: str) -> Callable[..., Any]:
    def refused(*args: Any, **kwargs: Any) -> Any:
        stack = getattr(sys.modules.get("xacro"), "filestack", None) or [None]
        raise RefusedExpression(stack[-1], f"python.{name}(...)", f"python.{name}: {why}")

    return refused


# --------------------------------------------------------------------------- what may be read


def readable(
    path: str, packages: Mapping[str, str], broad: Iterable[str]
) -> tuple[list[str], list[str], str | None]:
    """The directory trees and the files the expansion of ``path`` may read, and the directory
    withheld: the directory ``path`` is named in, unless it is one of ``broad`` (the user's home
    directory, the file system's root: a description's own directory is never one of those;
    it is then the one withheld), and each package's directory; ``path`` itself (the file a
    symbolic link names may lie elsewhere). Symbolic links resolved, relative paths from the
    working directory."""
    source = os.path.abspath(path)
    own = os.path.realpath(os.path.dirname(source))
    withheld = own if own in {os.path.realpath(b) for b in broad} else None
    trees = [own] if withheld is None else []
    trees += [os.path.realpath(t) for t in packages.values()]
    return trees, [os.path.realpath(source)], withheld


def _beneath(real: str, trees: list[str]) -> bool:
    """Whether the resolved path ``real`` is one of ``trees`` or lies beneath one."""
    return any(os.path.commonpath([real, t]) == t for t in trees)


def may_read(path: str, trees: list[str], files: list[str]) -> bool:
    """Whether ``path`` (symbolic links resolved) is one of ``files`` or lies beneath one of the
    directory ``trees`` (:func:`readable`'s answer)."""
    real = os.path.realpath(path)
    return real in files or _beneath(real, trees)


def _shown(path: str) -> str:
    """``path`` for a message, with the file it leads to if a symbolic link makes that another."""
    shown, real = os.path.normpath(path), os.path.realpath(path)
    return shown if real == os.path.abspath(shown) else f"{shown} (a link to {real})"


def _module_trees() -> list[str]:
    """The directories the modules loaded so far came from (symbolic links resolved), those
    beneath another left out."""
    found = set()
    for module in list(sys.modules.values()):
        file = getattr(module, "__file__", None)
        if isinstance(file, str) and os.path.isabs(file):
            found.add(os.path.dirname(os.path.realpath(file)))
    trees: list[str] = []
    for directory in sorted(found):  # a directory before those beneath it
        if not _beneath(directory, trees):
            trees.append(directory)
    return trees


def _reads(xacro: ModuleType, trees: list[str], files: list[str], withheld: str | None) -> None:
    """Refuse, with :class:`ReadRefused`, xacro's opening a file outside ``trees`` and
    ``files``, or listing a directory outside ``trees`` for an include's glob pattern
    (``withheld``: the SOURCE's directory not read, :func:`readable`)."""
    original_glob = xacro.glob.glob

    def checked_open(file: Any, *args: Any, **kwargs: Any) -> Any:
        if isinstance(file, str | bytes | os.PathLike):
            name = os.fsdecode(file)
            if not may_read(name, trees, files):
                raise ReadRefused(_shown(name), withheld)
        return builtins.open(file, *args, **kwargs)

    def checked_glob(pattern: str, *args: Any, **kwargs: Any) -> list[str]:
        fixed = []  # the pattern's leading directories without a wildcard: the one listed
        for part in os.path.dirname(pattern).split(os.sep):
            if GLOB_MAGIC.search(part):
                break
            fixed.append(part)
        directory = os.sep.join(fixed) or os.curdir
        if not may_read(directory, trees, []):
            raise ReadRefused(_shown(directory), withheld)
        return list(original_glob(pattern, *args, **kwargs))

    xacro.open = checked_open  # type: ignore[attr-defined] # found before the builtin open
    xacro.glob = types.SimpleNamespace(glob=checked_glob)  # type: ignore[attr-defined]


# --------------------------------------------------------------------------- ROS packages


@contextlib.contextmanager
def _packages(xacro: ModuleType, subst: ModuleType, paths: Mapping[str, str]) -> Iterator[None]:
    """Resolve ``$(find NAME)`` and ``package://NAME/`` from ``paths`` while xacro runs.

    xacro asks ROS's ament index for ``$(find)`` (``substitution_args._eval_find``) and opens
    other file names as paths (``abs_filename_spec``); both hooks are swapped for ours.
    """

    def find(package: str) -> str:
        if package not in paths:
            raise PackageMissing(package)
        return os.path.abspath(paths[package])

    original_spec = xacro.abs_filename_spec

    def filename_spec(spec: str) -> str:
        if spec.startswith(PACKAGE_URL):
            package, _, rest = spec[len(PACKAGE_URL) :].partition("/")
            return os.path.join(find(package), rest)
        return str(original_spec(spec))

    original_find = subst._eval_find
    subst._eval_find = find  # type: ignore[attr-defined]
    xacro.abs_filename_spec = filename_spec  # type: ignore[attr-defined]
    try:
        yield
    finally:
        subst._eval_find = original_find  # type: ignore[attr-defined]
        xacro.abs_filename_spec = original_spec  # type: ignore[attr-defined]


# --------------------------------------------------------------------------- the process


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _cause(error: BaseException) -> BaseException:
    """Ours (a refusal, a missing package) or memory exhaustion, where xacro wrapped it (as
    ``.exc`` or ``__cause__``); else ``error`` itself."""
    cause: BaseException | None = error
    while cause is not None:
        if isinstance(cause, RefusedExpression | ReadRefused | PackageMissing | MemoryError):
            return cause
        cause = cause.__cause__ or getattr(cause, "exc", None)
    return error


def _failure(error: BaseException) -> dict[str, str]:
    cause = _cause(error)
    if isinstance(cause, MemoryError):
        raise cause
    if isinstance(cause, RefusedExpression):
        shown = _one_line(cause.expression)
        if len(shown) > SHOWN_EXPRESSION:
            shown = shown[:SHOWN_EXPRESSION] + "..."
        return {"error": "refused", "message": cause.why, "expression": shown,
                "file": str(cause.file or "")}  # fmt: skip
    if isinstance(cause, ReadRefused):
        return {"error": "unreadable", "message": cause.file, "file": cause.file,
                "withheld": cause.withheld or ""}  # fmt: skip
    if isinstance(cause, PackageMissing):
        return {"error": "package", "message": cause.package, "package": cause.package}
    return {"error": "xacro", "message": _one_line(error) or type(error).__name__}


def _confine_module() -> ModuleType:
    """:mod:`.confine`, from its file beside this one when run as a script."""
    if __package__:
        from . import confine

        return confine
    import importlib.util

    spec = importlib.util.spec_from_file_location("confine", Path(__file__).with_name("confine.py"))
    if spec is None or spec.loader is None:
        raise ImportError("confine.py is missing beside xacro_child.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def expand(job: Mapping[str, Any]) -> tuple[dict[str, Any], bytes]:
    """Confine this process, then expand the job's file: the header and the URDF text."""
    confine = _confine_module()
    confine.limit(job["memory"], job["cpu"])
    confine.die_with_parent(job["parent"])
    sys.path.extend(d for d in job["module_dirs"] if d not in sys.path)
    try:  # everything the expansion imports, now: the guard refuses imports later
        import xml.dom.expatbuilder  # noqa: F401  (minidom imports it when it first parses)

        import xacro
        import xacro.substitution_args as subst
        import yaml  # noqa: F401
    except ImportError as e:
        return {"error": "no-xacro", "message": _one_line(e)}, b""
    _strict(xacro, subst)
    trees, files, withheld = readable(job["path"], job["packages"], job["broad"])
    _reads(xacro, trees, files, withheld)
    try:  # before the seccomp filter and the guard, which refuse ctypes
        landlock = confine.restrict_reading([*trees, *_module_trees()], files)
    except OSError as e:
        return {"error": "confine", "message": _one_line(e)}, b""
    confine.forbid_syscalls()
    opened: list[str] = []
    confine.guard(opened)
    try:
        with _packages(xacro, subst, job["packages"]):
            doc = xacro.process_file(job["path"], mappings=dict(job["args"]))
        text = str(doc.toprettyxml(indent="  ")).encode("utf-8")
    except Exception as e:  # xacro raises XacroException, expat errors, OSError, NameError...
        return _failure(e), b""
    return {"read": sorted(set(opened)), "landlock": landlock}, text


def main() -> None:
    """The process: a job on stdin, the result on stdout (see the module docstring)."""
    try:
        job = json.loads(sys.stdin.buffer.read())
        header, text = expand(job)
        out = sys.stdout.buffer
        out.write(json.dumps(header).encode("utf-8") + b"\n")
        out.write(text)
        out.flush()
    except MemoryError:
        os._exit(OUT_OF_MEMORY)


if __name__ == "__main__":
    main()
