"""The xacro expansion process (``docs/security.md``): run as a script by :mod:`urdf2dh.io.xacro`,
``python -I -S -B -X utf8 xacro_child.py``, so that nothing from the working directory,
``PYTHONPATH`` or the user's site-packages can be imported.

It reads a job (JSON) on stdin, confines itself (:mod:`.confine`), expands the file and writes on
stdout one line of JSON, then, on success, the URDF text:

* ``{"read": [FILE, ...]}`` and the URDF: every file the expansion opened;
* ``{"error": KIND, "message": TEXT, ...}``: KIND is ``refused`` (an expression the strict
  evaluation refuses; with ``file`` and ``expression``), ``package`` (a ROS package not given;
  with ``package``), ``no-xacro`` (the xacro package is not installed) or ``xacro`` (anything
  xacro reports).

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
import string
import sys
from collections.abc import Callable, Iterator, Mapping
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
    "RefusedExpression",
    "expand",
    "main",
    "refusal",
]

OUT_OF_MEMORY = 3
PACKAGE_URL = "package://"
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
        if isinstance(cause, RefusedExpression | PackageMissing | MemoryError):
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
    confine.forbid_syscalls()
    opened: list[str] = []
    confine.guard(opened)
    try:
        with _packages(xacro, subst, job["packages"]):
            doc = xacro.process_file(job["path"], mappings=dict(job["args"]))
        text = str(doc.toprettyxml(indent="  ")).encode("utf-8")
    except Exception as e:  # xacro raises XacroException, expat errors, OSError, NameError...
        return _failure(e), b""
    return {"read": sorted(set(opened))}, text


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
