"""yourdfpy's element parsers, without trimesh's package.

urdf2dh reads URDF elements with yourdfpy's own parsers (``URDF._parse_link``,
``URDF._parse_joint``, its ``Robot``). Its module ``yourdfpy/urdf.py`` starts with
``import trimesh`` and ``import trimesh.transformations as tra``; trimesh's package
``__init__`` imports scipy, networkx, PIL, shapely, rtree, embreex and manifold3d (over a
thousand modules, about 70 MiB) for meshes, which urdf2dh never loads. The element parsers use
only ``tra.compose_matrix``.

:data:`urdf` is therefore a private instance of yourdfpy's ``urdf.py``, executed from its installed
file by the standard import machinery under this module's name (``urdf2dh.io.urdf._yourdfpy.urdf``),
in which ``trimesh`` is a package object (``urdf2dh.io.urdf._yourdfpy.trimesh``) whose ``__path__``
is trimesh's directory but whose ``__init__`` never runs, so that ``trimesh.transformations`` loads
from trimesh's own file under this private name. The two modules it imports, ``typed`` (type names
for annotations) and ``util`` (``diagonal_dot`` and ``random_generator``, for quaternions and random
rotations, which the element parsers never compute), are placeholder modules here (:data:`STUBBED`):
the real ones import ``numpy.random``, ``zipfile``, ``uuid`` and more, a fifth of a conversion's
start-up. Two modules yourdfpy's module imports and its element parsers never use, ``logging``
and ``six``, are imported when first used (:data:`DEFERRED`, :class:`Deferred`): its module-level
``logging.getLogger(__name__)`` gives a :class:`Deferred` logger, which imports ``logging`` and
hands each call to the real logger of that name, so a message yourdfpy logs reaches the same
logger and handlers as before. The mapping is made by the private module's own ``__builtins__`` (its
``__import__`` sends ``trimesh`` and ``trimesh.<sub>`` here and every other name to the ordinary
import), so nothing else in the process is touched: ``sys.modules`` gains entries under this
module's name only, no finder or hook is installed, and a library user who imports ``trimesh`` or
``yourdfpy``, before or after, in any thread, gets the real packages. Other ways were weighed and
set aside:

* a stand-in ``trimesh`` put in ``sys.modules`` while yourdfpy is imported (or a finder
  installed for that time and removed after): another thread importing trimesh meanwhile would
  get the stand-in, and the real ``yourdfpy.urdf`` would keep it for good;
* importing trimesh lazily (``importlib.util.LazyLoader``): yourdfpy's module body reads
  ``trimesh.Trimesh`` and ``trimesh.Scene`` (in annotations) and ``trimesh.transformations``,
  which load the whole package at once;
* parsing the elements with code of our own: yourdfpy is the loader.

Names of trimesh's package that yourdfpy's module body mentions in annotations
(``trimesh.Trimesh``, ``trimesh.Scene``), and those ``transformations`` takes from ``typed`` and
``util``, are :class:`NotLoaded` placeholders here, which refuse any use (annotations may join them
with ``|``): only the mesh and random-rotation functions read them, and urdf2dh calls none.
Where the private instance cannot be made (another layout of yourdfpy or trimesh), :data:`urdf`
is the real ``yourdfpy.urdf``, imported as usual: slower, the same parsers.
"""

from __future__ import annotations

import builtins
import importlib
import importlib.machinery
import importlib.util
import sys
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["DEFERRED", "STUBBED", "Deferred", "NotLoaded", "urdf"]

#: trimesh's modules that the private package holds as placeholders (:class:`NotLoaded` names).
STUBBED = ("typed", "util")
#: Modules yourdfpy's module imports that are imported when it first uses them (:class:`Deferred`).
DEFERRED = ("logging", "six")


class NotLoaded:
    """A name of trimesh's package in the private copy, where that package is not loaded."""

    def __init__(self, name: str) -> None:
        self._name = name

    def _refuse(self) -> RuntimeError:
        return RuntimeError(
            f"trimesh.{self._name} is not loaded: urdf2dh's copy of yourdfpy reads URDF elements "
            "only (import yourdfpy for meshes)"
        )

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise self._refuse()

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        raise self._refuse()

    def __or__(self, other: object) -> NotLoaded:  # an annotation's ``Number | None``
        return self

    __ror__ = __or__

    def __repr__(self) -> str:
        return f"<trimesh.{self._name}, not loaded>"


class Deferred:
    """A module of :data:`DEFERRED` not imported yet, in the private copy: the module is imported
    when one of its names is first read. With ``logger``, the logger ``logging.getLogger(logger)``
    that ``logging`` is imported for on its first use (``getLogger`` itself imports nothing)."""

    def __init__(self, module: str, logger: str | None = None) -> None:
        self._module = module
        self._logger = logger

    def getLogger(self, name: str | None = None) -> Any:
        """``logging.getLogger(name)``, deferred (or, once ``logging`` is imported, at once)."""
        if "logging" in sys.modules:
            return sys.modules["logging"].getLogger(name)
        return Deferred("logging", name)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        module = importlib.import_module(self._module)
        if self._module == "logging" and self._logger is not None:
            return getattr(module.getLogger(self._logger), name)
        return getattr(module, name)

    def __repr__(self) -> str:
        what = f"logger {self._logger!r}" if self._logger is not None else self._module
        return f"<{what}, imported on first use>"


def _directory(package: str) -> str:
    """The directory of an installed top-level package, found without importing it."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise ImportError(f"{package} is not an installed package")
    return str(next(iter(spec.submodule_search_locations)))


def _not_loaded(prefix: str) -> Callable[[str], NotLoaded]:
    """A placeholder module's ``__getattr__`` (PEP 562): a :class:`NotLoaded` for each name, but
    none for dunder names (``__file__``, ...), which tools that walk ``sys.modules`` read."""

    def names(name: str) -> NotLoaded:
        if name.startswith("__"):
            raise AttributeError(name)
        return NotLoaded(prefix + name)

    return names


def _trimesh_package() -> types.ModuleType:
    """A package over trimesh's directory whose ``__init__`` is not run."""
    name = f"{__name__}.trimesh"
    spec = importlib.machinery.ModuleSpec(name, None, is_package=True)
    spec.submodule_search_locations = [_directory("trimesh")]
    package = importlib.util.module_from_spec(spec)
    vars(package)["__getattr__"] = _not_loaded("")  # PEP 562: the names that are not loaded
    sys.modules[name] = package
    for sub in STUBBED:
        stub = types.ModuleType(f"{name}.{sub}")
        vars(stub)["__getattr__"] = _not_loaded(f"{sub}.")
        sys.modules[stub.__name__] = stub
        setattr(package, sub, stub)
    return package


def _yourdfpy_module(package: types.ModuleType) -> types.ModuleType:
    """yourdfpy's ``urdf.py`` executed with ``trimesh`` meaning ``package``."""

    def import_(
        name: str,
        globals: Any = None,
        locals: Any = None,
        fromlist: Any = (),
        level: int = 0,
    ) -> Any:
        if level == 0 and name.split(".")[0] == "trimesh":
            module = importlib.import_module(package.__name__ + name[len("trimesh") :])
            return module if fromlist else package
        if level == 0 and name in DEFERRED and not fromlist and name not in sys.modules:
            return Deferred(name)
        return builtins.__import__(name, globals, locals, fromlist, level)

    name = f"{__name__}.urdf"
    path = Path(_directory("yourdfpy")) / "urdf.py"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"no module at {path}")
    module = importlib.util.module_from_spec(spec)
    module.__dict__["__builtins__"] = {**vars(builtins), "__import__": import_}
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _load() -> types.ModuleType:
    """The private instance of yourdfpy's module, or the real ``yourdfpy.urdf``."""
    try:
        return _yourdfpy_module(_trimesh_package())
    except Exception:  # another layout: the real module, with trimesh's whole package
        for name in [m for m in sys.modules if m.startswith(f"{__name__}.")]:
            del sys.modules[name]
        return importlib.import_module("yourdfpy.urdf")


urdf = _load()
