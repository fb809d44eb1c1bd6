"""What a convention is: the :class:`Convention` protocol, its parameter records and its result.

A convention module defines

* frozen parameter dataclasses (subclasses of :class:`Params`) for its base, rows and tool, each
  field declared with its quantity (:func:`angle`, :func:`length`, :func:`direction`,
  :func:`offset`) and each record knowing its own transform (:meth:`Params.frame`, or for a row
  :meth:`Params.around_joint`: the constant transforms before and after the joint motion);
* one object satisfying :class:`Convention`: its name, the FK formula texts, the parameter
  classes a table file may hold in each place, the styles it takes, and ``from_poe``.

Everything else (table files, text formats, diff, exports, plots, the reference FK) reads the
records through this interface, so a new convention is its module and one registry line
(:mod:`urdf2dh.conventions`). Nothing here imports numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, ClassVar, Literal, Protocol

from ..checks import unchecked
from ..geometry.frames import Frame, wrap_angle
from ..geometry.normals import Judgement

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = [
    "Column",
    "Convention",
    "Conversion",
    "Guide",
    "Params",
    "Part",
    "Quantity",
    "Style",
    "angle",
    "columns",
    "direction",
    "length",
    "offset",
    "unit_direction",
    "written_angle",
    "written_length",
]

Quantity = Literal["angle", "length", "direction", "offset"]
"""``angle`` (rad), ``length`` (source unit), ``direction`` (unit 3-vector), ``offset``
(3-vector of lengths)."""

Part = Literal["base", "row", "tool"]


def angle() -> Any:
    """A field holding an angle in radians."""
    return field(metadata={"quantity": "angle"})


def length() -> Any:
    """A field holding a length in the source's unit."""
    return field(metadata={"quantity": "length"})


def direction() -> Any:
    """A field holding a unit 3-vector."""
    return field(metadata={"quantity": "direction"})


def offset() -> Any:
    """A field holding a 3-vector of lengths."""
    return field(metadata={"quantity": "offset"})


Value = float | tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Params:
    """Base of every parameter record: a frozen dataclass whose fields are its parameters."""

    VECTOR: ClassVar[tuple[str, ...]] = ("direction", "offset")
    form: ClassVar[str] = ""
    """Its name where a convention's rows take several forms (``D-H``, ``Hayati``)."""

    def __post_init__(self) -> None:
        for name, quantity in _layout(type(self)):
            value = getattr(self, name)
            if quantity in self.VECTOR:
                x, y, z = value
                object.__setattr__(self, name, (float(x), float(y), float(z)))
            else:
                object.__setattr__(self, name, float(value))

    @classmethod
    def quantities(cls) -> dict[str, Quantity]:
        """Parameter name -> quantity, in declaration order."""
        return dict(_layout(cls))

    def values(self) -> dict[str, Value]:
        """Parameter name -> value, in declaration order."""
        return {name: getattr(self, name) for name, _ in _layout(type(self))}

    def scalars(self) -> dict[str, float]:
        """The parameters that are single numbers (angles and lengths), by name."""
        return {k: v for k, v in self.values().items() if not isinstance(v, tuple)}

    def vectors(self) -> dict[str, tuple[float, float, float]]:
        """The parameters that are 3-vectors (directions and offsets), by name."""
        return {k: v for k, v in self.values().items() if isinstance(v, tuple)}

    def to_dict(self) -> dict[str, float | list[float]]:
        """The table file's ``params`` mapping (vectors as lists)."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in self.values().items()}

    def written(self, angle: float, length: float) -> Params:
        """The record as a table file writes it: a value within ``length`` of 0 (an angle
        within ``angle`` of a multiple of pi/2) replaced by that, a direction's components within
        ``angle`` of 0 made 0 and the direction normalised again (:func:`unit_direction`), and
        no ``-0.0``."""
        values: dict[str, Value] = {}
        for name, quantity in _layout(type(self)):
            value = getattr(self, name)
            if quantity == "angle":
                values[name] = written_angle(value, angle)
            elif quantity == "length":
                values[name] = written_length(value, length)
            elif quantity == "direction":
                x, y, z = (written_length(c, angle) for c in value)
                values[name] = unit_direction((x, y, z))
            else:
                x, y, z = (_snap(c, (0.0,), length) for c in value)
                values[name] = (x, y, z)
        # every value a float or a tuple of floats already, as the constructor makes them
        return unchecked(type(self), *values.values())

    def frame(self) -> Frame:
        """The record's transform (base and tool records; rows: see :meth:`around_joint`)."""
        raise NotImplementedError

    def around_joint(self) -> tuple[Frame | None, Frame]:
        """A row's constant transforms ``(before Q_i, after Q_i)``; ``None``: nothing before."""
        return None, self.frame()


_LAYOUTS: dict[type, tuple[tuple[str, Quantity], ...]] = {}


def _layout(cls: type) -> tuple[tuple[str, Quantity], ...]:
    """A record class's parameters and their quantities, in declaration order (looked up once
    per class: every record made or written reads them)."""
    if cls not in _LAYOUTS:
        _LAYOUTS[cls] = tuple((f.name, f.metadata["quantity"]) for f in fields(cls))
    return _LAYOUTS[cls]


def unit_direction(v: tuple[float, float, float]) -> tuple[float, float, float]:
    """``v / |v|`` (``v`` non-zero), with a coordinate axis exactly: ``(0, 0, -1)``, never
    ``(0, 0, -0.9999999999999999)``; no ``-0.0``.

    How a direction is written and read back, so that its norm is 1 to the last place and a
    reader that evaluates it as written (CPC's ``R(b)``, Sumenkov eq. 4) gets the rotation the
    table was checked with."""
    x, y, z = v
    n = math.hypot(x, y, z)
    return (x / n + 0.0, y / n + 0.0, z / n + 0.0)


def _snap(value: float, targets: tuple[float, ...], within: float) -> float:
    for target in targets:
        if abs(value - target) <= within:
            return target
    return value + 0.0  # -0.0 -> 0.0


def written_length(value: float, within: float) -> float:
    """A length as files write it: 0 when within ``within`` of 0, never ``-0.0``."""
    return _snap(value, (0.0,), within)


def written_angle(value: float, within: float, wrap: bool = True) -> float:
    """An angle as files write it: the multiple of pi/2 (in [-pi, pi], pi for -pi; where not
    ``wrap``, the multiple itself, as a joint limit of 4 pi needs) when within ``within`` of
    one, never ``-0.0``; other values are kept."""
    quarter = round(value / (0.5 * math.pi))
    if abs(value - quarter * 0.5 * math.pi) > within:
        return value + 0.0
    return wrap_angle(quarter * 0.5 * math.pi) if wrap else quarter * 0.5 * math.pi + 0.0


@dataclass(frozen=True, slots=True)
class Guide:
    """Frames a D-H table's free choices follow, in place of a named style: for each line the
    table puts a frame's z axis on (after the base z: each joint's axis, then the tool's z), the
    frame it should come nearest, in the model's base frame.

    Of the equally exact frames on a line (the common normal's two directions; for parallel
    axes, where along them the normal lies; for coincident ones, any turn and height), the
    conversion takes the one nearest the guide's; :func:`urdf2dh.match` writes a table in the
    layout of the one a person wrote this way."""

    frames: tuple[Frame, ...]

    def __str__(self) -> str:
        return "guided"


Style = str | Guide
"""What chooses among equally exact tables: a style's name (``wu``, ``ur``, ``zero``) or a
:class:`Guide`."""


@dataclass(frozen=True, slots=True)
class Conversion:
    """What ``from_poe`` makes of a model: records for the base, each joint and the tool, each
    joint's sign (``-1`` where the convention moves it against its frame's z), the tolerance
    judgements made (reported with the deviation they cause) and notes for the warnings."""

    base: Params
    rows: tuple[Params, ...]
    tool: Params
    signs: tuple[float, ...]
    judgements: tuple[Judgement, ...] = ()
    notes: tuple[str, ...] = ()


class Convention(Protocol):
    """A kinematic parameter convention: its name, its table's parameters and forward kinematics
    (docs/conventions/dh.md, mdh.md, cpc.md, hayati.md), and the conversion from a POE model."""

    name: str
    """Its name in the table file, on the command line and in the registry (``dh``)."""
    label: str
    """A short name for people (``standard D-H``)."""
    title: str
    """The FK formula as the text and Markdown tables print it."""
    formula: str
    """The FK formula as exported files state it."""
    base_types: tuple[type[Params], ...]
    row_types: tuple[type[Params], ...]
    tool_types: tuple[type[Params], ...]
    """The parameter records each place may hold (a table file's ``params`` keys pick one)."""
    styles: tuple[str, ...]
    """The styles it takes, the default first (see :mod:`urdf2dh.conventions.dh`)."""
    guided: bool
    """Whether it takes a :class:`Guide` for its style."""

    def from_poe(self, model: PoeModel, tol: Tolerances, style: Style) -> Conversion:
        """The table of ``model`` in this convention, unchecked
        (:func:`urdf2dh.conventions.convert.to_table`
        checks it)."""
        ...


@dataclass(frozen=True, slots=True)
class Column:
    """A parameter column of the flat formats: its name and quantity."""

    name: str
    quantity: Quantity


def columns(conv: Convention) -> list[Column]:
    """Every parameter a table of ``conv`` may hold, rows' first, in declaration order."""
    out: dict[str, Quantity] = {}
    for cls in (*conv.row_types, *conv.base_types, *conv.tool_types):
        for name, quantity in cls.quantities().items():
            out.setdefault(name, quantity)
    return [Column(k, v) for k, v in out.items()]
