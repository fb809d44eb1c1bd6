"""xacro input: expand a ``.xacro`` file to URDF text with the ``xacro`` package (optional).

ROS packages are not needed: ``$(find NAME)`` and ``package://NAME/...`` in file names that
xacro opens (includes, ``xacro.load_yaml``) resolve to the directories given as
``--package-path NAME=DIR``. A package that is not given is a one-line error naming it.
``package://`` mesh file names in the expanded URDF are left as they are: meshes are never
loaded.
"""

from __future__ import annotations

import contextlib
import importlib
import os
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from .errors import InputError

__all__ = ["PackageNotFound", "expand"]

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
            f"{display}: reading .xacro files needs the xacro package; install it with: "
            "pip install xacro  (or pip install 'urdf2dh[xacro]')"
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
            package, _, rest = spec[len(PACKAGE_URL):].partition("/")
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


def expand(path: Path, display: str, package_paths: Mapping[str, str] | None = None,
           mappings: Mapping[str, str] | None = None) -> bytes:
    """The URDF text of the xacro file ``path`` (``mappings``: xacro arguments NAME:=VALUE)."""
    xacro = _xacro(display)
    for name, directory in (package_paths or {}).items():
        if not Path(directory).is_dir():
            raise InputError(f"--package-path {name}={directory}: no such directory")
    try:
        with _packages(xacro, display, package_paths or {}):
            doc = xacro.process_file(str(path), mappings=dict(mappings or {}))
    except InputError:
        raise
    except Exception as e:  # xacro raises XacroException, expat errors, IOError, NameError...
        cause: BaseException | None = e
        while cause is not None:  # xacro may wrap our PackageNotFound (as .exc or __cause__)
            if isinstance(cause, InputError):
                raise cause from e
            cause = cause.__cause__ or getattr(cause, "exc", None)
        text = " ".join(str(e).split()) or type(e).__name__
        raise InputError(f"{display}: xacro cannot expand it ({text})") from e
    return str(doc.toprettyxml(indent="  ")).encode("utf-8")
