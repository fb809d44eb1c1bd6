"""xacro input: expand a ``.xacro`` file to URDF text with the ``xacro`` package (optional).

ROS packages are not needed: ``$(find NAME)`` and ``package://NAME/...`` in file names that
xacro opens (includes, ``xacro.load_yaml``) resolve to the directories given as
``--package-path NAME=DIR``. A package that is not given is a one-line error naming it.
``--xacro-arg NAME:=VALUE`` sets the file's ``<xacro:arg>`` values. ``package://`` mesh file
names in the expanded URDF are left as they are: meshes are never loaded.

A xacro file is a program: xacro evaluates the Python expressions in it (``${...}``,
``$(eval ...)``). The expansion runs in a confined child process (:mod:`urdf2dh.io`,
``docs/security.md``): started isolated from the working directory and ``PYTHONPATH``, with an
empty environment, refused processes, sockets and file changes, its expressions checked before
xacro evaluates them, and bounded in time and memory (:class:`XacroOptions`: 20 s and 1 GiB by
default, ``--xacro-timeout`` and ``--xacro-memory`` to raise them) and in what it prints
(:data:`URDF_LIMIT`, :data:`MESSAGES_LIMIT`). Hitting a bound, or an expression refused, is a
one-line error naming it. Everything the child starts is killed when it ends.

The expansion may read beneath the SOURCE's directory (the one its path names, symbolic links
resolved) and the package directories only: an include, ``xacro.load_yaml`` or an include's glob
pattern reaching any other file is a one-line error naming it (give its directory with
``--package-path``); on Linux, Landlock has the kernel refuse any other read too. The files the
expansion read are inputs of the run (:func:`urdf2dh.io.files.note_input`): no output replaces
them.
"""

from __future__ import annotations

import importlib.machinery
import math
import os
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, Remedy
from ..tolerances import FILE_BYTES
from .files import note_input

if TYPE_CHECKING:
    from .child import Finished
    from .sources import Content, Reading, Source

__all__ = [
    "MESSAGES_LIMIT",
    "URDF_LIMIT",
    "PackageNotFound",
    "XacroOptions",
    "expand",
    "read_source",
]

URDF_LIMIT = FILE_BYTES  # bytes of expanded URDF: as many as a URDF file may hold
MESSAGES_LIMIT = 2**20  # bytes the expansion may print (xacro.message, warnings)


@dataclass(frozen=True, slots=True)
class XacroOptions:
    """How to expand ``.xacro`` sources.

    Attributes
    ----------
    packages
        ROS package name -> directory (``--package-path``). The expansion may read beneath these
        directories and the SOURCE's, nowhere else; a name no ``$(find)`` uses gives a
        directory to read only.
    args
        xacro argument name -> value (``--xacro-arg NAME:=VALUE``).
    timeout
        Seconds the expansion may take.
    memory
        MiB of address space the expanding process may use.
    """

    packages: Mapping[str, str] = field(default_factory=dict)
    args: Mapping[str, str] = field(default_factory=dict)
    timeout: float = 20.0
    memory: int = 1024

    def __post_init__(self) -> None:
        if not (self.timeout > 0.0 and self.memory > 0):
            raise ValueError("xacro limits must be positive")


class PackageNotFound(InputError):
    """A ``$(find NAME)`` or ``package://NAME`` with no ``--package-path NAME=DIR``."""

    def __init__(self, display: str, package: str) -> None:
        super().__init__(
            f"{display}: xacro needs ROS package '{package}'",
            remedy=Remedy("xacro.packages", "; point at its directory with {}", f"{package}=DIR"),
        )
        self.package = package


CHILD = Path(__file__).resolve().parent / "xacro_child.py"
UNDEFINED_ARG = "Undefined substitution argument "  # xacro's words for a missing $(arg)
INSTALL_HINT = "pip install xacro"
READ_ROLE = "a file the xacro SOURCE read"


def module_dirs(display: str) -> list[str]:
    """The directories the child imports ``xacro`` and ``yaml`` from: where this interpreter
    finds them on its ``sys.path``, the working directory left out (a module there is not
    installed: it may be anybody's)."""
    path = [p for p in sys.path if p and os.path.isabs(p) and not _is_cwd(p)]
    dirs = []
    for name in ("xacro", "yaml"):
        blocked = name in sys.modules and sys.modules[name] is None  # `import` refuses it here
        spec = None if blocked else importlib.machinery.PathFinder.find_spec(name, path)
        if spec is None or spec.origin is None:
            if name == "xacro":
                raise InputError(
                    f"{display}: reading .xacro files needs the xacro package (a dependency of "
                    "urdf2dh, missing here); install it with: " + INSTALL_HINT
                )
            continue
        top = Path(spec.origin).parent if Path(spec.origin).name == "__init__.py" else None
        directory = str((top or Path(spec.origin)).parent)
        if directory not in dirs:
            dirs.append(directory)
    return dirs


def _is_cwd(directory: str) -> bool:
    try:
        return os.path.samefile(directory, os.getcwd())
    except OSError:
        return False


def _environment() -> dict[str, str]:
    """The child's environment: empty but for what the interpreter itself may need to start."""
    return {k: v for k, v in os.environ.items() if k in ("LD_LIBRARY_PATH", "SYSTEMROOT")}


def expand(path: Path, display: str, options: XacroOptions | None = None) -> bytes:
    """The URDF text of the xacro file ``path``, expanded in a confined child process within the
    time and memory of ``options`` (see the module docstring)."""
    import json

    from . import child
    from .xacro_child import OUT_OF_MEMORY

    options = options or XacroOptions()
    dirs = module_dirs(display)
    for name, directory in options.packages.items():
        if not Path(directory).is_dir():
            raise InputError(f"package {name}={directory}: no such directory")
    if not sys.executable:
        raise InputError(f"{display}: no Python interpreter to expand xacro with")
    try:
        done = child.run(
            child_argv(), job(path, options, dirs), _environment(), options.timeout,
            URDF_LIMIT + 2**20, MESSAGES_LIMIT,
        )  # fmt: skip
    except child.TimedOut:
        raise InputError(
            f"{display}: xacro expansion took longer than {options.timeout:g} s",
            remedy=Remedy("xacro.timeout", " ({} allows more)", "SECONDS"),
        ) from None
    except child.Overflow as e:
        what = "expanded URDF" if e.stream == "stdout" else "messages"
        raise InputError(
            f"{display}: xacro expansion printed more than {e.limit // 2**20} MiB of {what}; "
            "stopped"
        ) from None
    if done.returncode == OUT_OF_MEMORY:
        raise InputError(
            f"{display}: xacro expansion needs more than {options.memory} MiB of memory",
            remedy=Remedy("xacro.memory", " ({} allows more)", "MIB"),
        )
    header, _, text = done.stdout.partition(b"\n")
    try:
        result = json.loads(header) if done.returncode == 0 else None
    except ValueError:
        result = None
    if not isinstance(result, dict):
        return _crashed(display, done)
    if "error" in result:
        raise _error(display, result)
    for file in result.get("read", []):
        note_input(file, READ_ROLE)
    return text


def read_source(content: Content, reading: Reading) -> Source:
    """The SOURCE of a ``.xacro`` file: expanded (with ``reading.xacro``), then read as URDF
    (the ``xacro`` entry of :data:`~urdf2dh.io.sources.READERS`)."""
    from .urdf import urdf_source

    return urdf_source(content, expand(content.path, content.display, reading.xacro), reading)


def child_argv() -> list[str]:
    """The command line of the expansion process (:mod:`.xacro_child`)."""
    return [sys.executable, "-I", "-S", "-B", "-X", "utf8", str(CHILD)]


def job(path: Path, options: XacroOptions, module_dirs: list[str]) -> bytes:
    """The expansion process's job (its standard input): expand ``path`` with ``options``,
    importing xacro and yaml from ``module_dirs``, as this process's child."""
    import json

    return json.dumps({
        "path": str(path),
        "packages": dict(options.packages),
        "args": dict(options.args),
        "memory": options.memory * 2**20,
        "cpu": math.ceil(options.timeout) + 1,
        "parent": os.getpid(),
        "module_dirs": module_dirs,
        "broad": broad_directories(),
    }).encode("utf-8")  # fmt: skip


def broad_directories() -> list[str]:
    """Directories whose files the expansion does not read for being the SOURCE's own: the
    user's home directory and the file system's root (a SOURCE directly in one of them would
    open it all, ``~/.ssh`` included)."""
    out = [os.path.abspath(os.sep)]
    try:
        out.append(str(Path.home()))
    except (RuntimeError, KeyError):  # no home directory to be found
        pass
    return out


def _crashed(display: str, done: Finished) -> bytes:
    """The one-line error of a child that ended without its answer."""
    if done.returncode < 0:
        how = f"was killed by signal {-done.returncode}"
    else:
        last = done.stderr_tail.decode("utf-8", "replace").strip().splitlines()
        how = f"failed (exit {done.returncode}{': ' + last[-1] if last else ''})"
    raise InputError(f"{display}: xacro expansion {how}")


def _error(display: str, result: Mapping[str, str]) -> InputError:
    """The one-line error of a failed expansion."""
    kind, text = result.get("error"), result.get("message", "")
    if kind == "package":
        return PackageNotFound(display, result["package"])
    if kind == "no-xacro":
        return InputError(
            f"{display}: reading .xacro files needs the xacro package ({text}); install it "
            f"with: {INSTALL_HINT}"
        )
    if kind == "unreadable":
        withheld = result.get("withheld")
        if withheld:
            why = (
                f"the SOURCE lies directly in {withheld}, whose files a description may not read "
                "(docs/security.md); put the description in a directory of its own"
            )
            then = ", or give one that holds the file with {}"
        else:
            why = (
                "it is outside the SOURCE's directory and the package directories "
                "(docs/security.md)"
            )
            then = "; give a directory that holds it with {}"
        return InputError(
            f"{display}: xacro may not read {result.get('file', text)}: {why}",
            remedy=Remedy("xacro.packages", then, "NAME=DIR"),
        )
    if kind == "confine":
        return InputError(f"{display}: xacro expansion could not be confined ({text})")
    if kind == "refused":
        where = result.get("file") or ""
        place = f" in {where}" if where and not _same_path(where, display) else ""
        return InputError(
            f"{display}: refused xacro expression ${{{result.get('expression', '')}}}{place}: "
            f"{text} (docs/security.md)"
        )
    remedy = None
    if text.startswith(UNDEFINED_ARG):
        name = text[len(UNDEFINED_ARG) :].split()[0]
        remedy = Remedy("xacro.args", "; pass it as {}", f"{name}:=VALUE")
    return InputError(f"{display}: xacro cannot expand it ({text})", remedy=remedy)


def _same_path(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a == b
