"""xacro input: expand a ``.xacro`` file to URDF text with the ``xacro`` package (optional).

ROS packages are not needed: ``$(find NAME)`` and ``package://NAME/...`` in file names that
xacro opens (includes, ``xacro.load_yaml``) resolve to the directories given as
``--package-path NAME=DIR``. A package that is not given is a one-line error naming it.
``--xacro-arg NAME:=VALUE`` sets the file's ``<xacro:arg>`` values. ``package://`` mesh file
names in the expanded URDF are left as they are: meshes are never loaded.

xacro evaluates Python expressions (``${...}``), so a file can ask for anything: ``${9**9**9}``
never ends, ``${'x'*10**9}`` wants gigabytes. The expansion runs in a child process bounded in
time and memory (:class:`XacroOptions`: 20 s and 1 GiB by default, ``--xacro-timeout`` and
``--xacro-memory`` to raise them); hitting a bound is a one-line error naming it.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import subprocess
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import InputError

__all__ = ["PackageNotFound", "XacroOptions", "expand"]


@dataclass(frozen=True, slots=True)
class XacroOptions:
    """How to expand ``.xacro`` sources.

    Attributes
    ----------
    packages
        ROS package name -> directory (``--package-path``).
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


PACKAGE_URL = "package://"


class PackageNotFound(InputError):
    """A ``$(find NAME)`` or ``package://NAME`` with no ``--package-path NAME=DIR``."""

    def __init__(self, display: str, package: str) -> None:
        super().__init__(
            f"{display}: xacro needs ROS package '{package}'; point at its directory with "
            f"--package-path {package}=DIR"
        )
        self.package = package


def _xacro(display: str) -> Any:
    try:
        import xacro
    except ImportError as e:
        raise InputError(
            f"{display}: reading .xacro files needs the xacro package (a dependency of "
            "urdf2dh, missing here); install it with: pip install xacro"
        ) from e
    return xacro


@contextlib.contextmanager
def _packages(xacro: Any, display: str, paths: Mapping[str, str]) -> Iterator[None]:
    """Resolve ``$(find NAME)`` and ``package://NAME/`` from ``paths`` while xacro runs.

    xacro asks ROS's ament index for ``$(find)`` (``substitution_args._eval_find``) and opens
    other file names as paths (``abs_filename_spec``); both hooks are swapped for ours and put
    back afterwards.
    """
    subst: Any = importlib.import_module("xacro.substitution_args")

    def find(package: str) -> str:
        if package not in paths:
            raise PackageNotFound(display, package)
        return os.path.abspath(paths[package])

    original_spec = xacro.abs_filename_spec

    def filename_spec(spec: str) -> str:
        if spec.startswith(PACKAGE_URL):
            package, _, rest = spec[len(PACKAGE_URL) :].partition("/")
            return os.path.join(find(package), rest)
        return str(original_spec(spec))

    original_find = subst._eval_find
    subst._eval_find = find
    xacro.abs_filename_spec = filename_spec
    try:
        yield
    finally:
        subst._eval_find = original_find
        xacro.abs_filename_spec = original_spec


def expand(path: Path, display: str, options: XacroOptions | None = None) -> bytes:
    """The URDF text of the xacro file ``path``, expanded in a child process within the time and
    memory of ``options``."""
    options = options or XacroOptions()
    _xacro(display)  # installed, or an install hint now rather than from the child
    for name, directory in options.packages.items():
        if not Path(directory).is_dir():
            raise InputError(f"--package-path {name}={directory}: no such directory")
    job = {"path": str(path), "display": display, "packages": dict(options.packages),
           "args": dict(options.args), "memory": options.memory}  # fmt: skip
    here = str(Path(__file__).resolve().parents[1])  # where urdf2dh is imported from
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [here, *filter(None, [os.environ.get("PYTHONPATH")])])}  # fmt: skip
    try:
        done = subprocess.run(
            [sys.executable, "-c", "from urdf2dh.xacro import _child; _child()"],
            input=json.dumps(job).encode(), capture_output=True, timeout=options.timeout,
            env=env, check=False,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        raise InputError(
            f"{display}: xacro expansion took longer than {options.timeout:g} s "
            "(--xacro-timeout SECONDS allows more)"
        ) from None
    if done.returncode == 0:
        return done.stdout
    if done.returncode == _OUT_OF_MEMORY:
        raise InputError(
            f"{display}: xacro expansion needs more than {options.memory} MiB of memory "
            "(--xacro-memory MIB allows more)"
        )
    message = done.stderr.decode("utf-8", "replace").strip().splitlines()
    raise InputError(message[-1] if message else f"{display}: xacro failed ({done.returncode})")


_OUT_OF_MEMORY = 3
UNDEFINED_ARG = "Undefined substitution argument "  # xacro's words for a missing $(arg)


def _child() -> None:
    """The expanding process: a job on stdin, URDF text on stdout, or a one-line error on
    stderr (exit 1; exit 3 when out of memory)."""
    job = json.load(sys.stdin)
    try:
        import resource

        limit = job["memory"] * 2**20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    except (ImportError, ValueError, OSError):  # no such limit on this platform
        pass
    try:
        text = _expand_here(Path(job["path"]), job["display"], job["packages"], job["args"])
    except MemoryError:
        sys.exit(_OUT_OF_MEMORY)
    except InputError as e:
        sys.stderr.write(" ".join(str(e).split()) + "\n")
        sys.exit(1)
    sys.stdout.buffer.write(text)


def _expand_here(path: Path, display: str, packages: Mapping[str, str],
                 mappings: Mapping[str, str]) -> bytes:  # fmt: skip
    """The expansion itself, in this process."""
    xacro = _xacro(display)
    try:
        with _packages(xacro, display, packages):
            doc = xacro.process_file(str(path), mappings=dict(mappings))
    except InputError:
        raise
    except MemoryError:
        raise
    except Exception as e:  # xacro raises XacroException, expat errors, IOError, NameError...
        cause: BaseException | None = e
        while cause is not None:  # xacro may wrap our PackageNotFound (as .exc or __cause__)
            if isinstance(cause, InputError):
                raise cause from e
            if isinstance(cause, MemoryError):
                raise cause from e
            cause = cause.__cause__ or getattr(cause, "exc", None)
        text = " ".join(str(e).split()) or type(e).__name__
        hint = ""
        if text.startswith(UNDEFINED_ARG):
            name = text[len(UNDEFINED_ARG) :].split()[0]
            hint = f"; pass it as --xacro-arg {name}:=VALUE"
        raise InputError(f"{display}: xacro cannot expand it ({text}){hint}") from e
    return str(doc.toprettyxml(indent="  ")).encode("utf-8")
