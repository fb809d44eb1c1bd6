"""The Table value type shared by every convention: rows, base and tool, its forward kinematics,
its POE model, and its JSON / YAML tree (docs/formats/table-file.md).

Whatever the convention, a table's forward kinematics has the shape::

    T(q) = B . prod_i [A_i . Q_i(s_i) . C_i] . T,  Q_i(s) = Rz(j_i s) Tz(k_i s),  s_i = scale_i q_i

with ``(A_i, C_i)`` the constant transforms around row ``i``'s joint motion
(:meth:`~urdf2dh.conventions.base.Params.around_joint`; ``dh``: ``A = I``, ``C = Rz Tz Rx Tx``).
The table folds them into ``n + 1`` constant links ``G_0 Q_1 G_1 ... Q_n G_n`` and evaluates
that with the reference FK (:mod:`urdf2dh.model.fk`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..checks import check_configurations, check_count, check_instance, check_real
from ..errors import missing, shown, visible
from ..geometry import frames, se3
from ..model._fastfk import chain_fk
from ..model.mimic import Mimic, actuated, row_positions
from ..model.poe import Joint, JointKind, JointMotion, PoeModel, check_motion
from ..schemas import TABLE_FILE
from ..tolerances import DEFAULT
from . import Convention, Params, get
from .grid import flat_columns, markdown, records, text

__all__ = ["SCHEMA", "Check", "Row", "Table"]

SCHEMA = TABLE_FILE  # the ``schema`` a table file is written with (docs/formats/table-file.md)

Mat = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Row(JointMotion):
    """One movable joint's row of a table.

    Attributes
    ----------
    name
        The joint's name.
    kind
        ``revolute``, ``prismatic`` or ``helical``.
    params
        The convention's record for the row (:class:`~urdf2dh.conventions.dh.DhLink`, ...):
        angles in radians, lengths in the table's length unit.
    pitch, scale
        The helix pitch (length per radian) and ``s = scale * q``, as :class:`~urdf2dh.Joint`.
    lower, upper
        The joint's limits (radians or length unit), or ``None``.
    mimic
        Whom it follows if it mimics another row's joint (the table is driven by the rows
        without ``mimic``, in order; docs/trees-mimic.md), else ``None``.
    """

    name: str
    kind: JointKind
    params: Params
    pitch: float = 0.0
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None
    mimic: Mimic | None = None

    def __post_init__(self) -> None:
        where = f"row {shown(self.name)}" if isinstance(self.name, str) else "Row"
        check_motion(self, where)
        check_instance(self.params, Params, f"{where}: params", "a convention's record")


@dataclass(frozen=True, slots=True)
class Check:
    """The conversion's own self-check: table FK against the source's POE FK.

    Attributes
    ----------
    samples
        Configurations compared.
    max_position_error, max_rotation_error
        The worst differences found there (length unit, rad).
    declared_position, declared_rotation
        The deviation the table declares, a bound that holds at every configuration (0 for an
        exact table; see :func:`urdf2dh.conventions.convert.to_table`).
    """

    samples: int
    max_position_error: float
    max_rotation_error: float
    declared_position: float = 0.0
    declared_rotation: float = 0.0

    def __post_init__(self) -> None:
        check_count(self.samples, "Check: samples")  # a check at no configuration checks nothing


def _check_record(record: Params, kinds: tuple[type[Params], ...], where: str) -> None:
    if not isinstance(record, kinds):
        expected = " or ".join(k.__name__ for k in kinds)
        raise TypeError(f"{where} must be a {expected}, not {type(record).__name__}")


@dataclass(frozen=True, slots=True)
class Table:
    """A kinematic parameter table in one convention.

    Attributes
    ----------
    convention
        Its name in :data:`urdf2dh.conventions.REGISTRY` (``dh``, ``mdh``, ``cpc``, ...).
    base, rows, tool
        The base record, one :class:`Row` per movable joint from base to tip, the tool record.
    size
        The robot's size in ``length_unit`` (:meth:`urdf2dh.model.poe.PoeModel.size`): what
        position errors and round-off are measured against.
    robot, source, base_link, tip_link, length_unit
        Provenance.
    check
        The self-check that produced it (``None`` for a table not yet checked).
    warnings
        Every judgement a user should know of, one message each.
    """

    convention: str
    base: Params
    rows: tuple[Row, ...]
    tool: Params
    size: float = 1.0
    robot: str = ""
    source: str = ""
    base_link: str = ""
    tip_link: str = ""
    length_unit: str = "m"
    check: Check | None = None
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        conv = get(self.convention)  # a known convention, or a UsageError naming the valid ones
        object.__setattr__(self, "rows", tuple(self.rows))
        object.__setattr__(self, "warnings", tuple(self.warnings))
        _check_record(self.base, conv.base_types, f"Table: base ({conv.name} base record)")
        _check_record(self.tool, conv.tool_types, f"Table: tool ({conv.name} tool record)")
        for i, row in enumerate(self.rows):
            check_instance(row, Row, f"Table: rows[{i}]")
            where = f"Table: row {shown(row.name)} ({conv.name} row)"
            _check_record(row.params, conv.row_types, f"{where}: params")
        if not check_real(self.size, "Table: size") > 0.0:
            raise ValueError(f"Table: size must be positive, not {self.size!r}")
        for name in ("robot", "source", "base_link", "tip_link", "length_unit"):
            check_instance(getattr(self, name), str, f"Table: {name}")
        if self.check is not None:
            check_instance(self.check, Check, "Table: check")

    @property
    def spec(self) -> Convention:
        """The convention object (formulas, parameter records)."""
        return get(self.convention)

    @property
    def n(self) -> int:
        """Number of rows (movable joints, the mimicking ones included)."""
        return len(self.rows)

    @property
    def dof(self) -> int:
        """Number of actuated rows: the length of a configuration ``q``."""
        return len(actuated(self.rows))

    @property
    def base_matrix(self) -> Mat:
        """``(4, 4)`` base transform ``B``."""
        return se3.matrix_of(self.base.frame())

    @property
    def tool_matrix(self) -> Mat:
        """``(4, 4)`` tool transform ``T``."""
        return se3.matrix_of(self.tool.frame())

    def link_form(self) -> tuple[Mat, Mat]:
        """The FK as links ``G_0 .. G_n`` ``(n + 1, 4, 4)`` and, per joint, the rotation and
        translation of ``Q_i`` per unit of ``q`` ``(n, 2)``: ``T(q) = G_0 Q_1 G_1 ... Q_n G_n``."""
        links: list[frames.Frame] = []
        g = self.base.frame()
        for row in self.rows:
            before, after = row.params.around_joint()
            links.append(g if before is None else frames.compose(g, before))
            g = after
        links.append(frames.compose(g, self.tool.frame()))
        motions = [(r.rotation * r.scale, r.translation * r.scale) for r in self.rows]
        return se3.stack(links), np.array(motions, dtype=float).reshape(-1, 2)

    def positions(self, q: NDArray[np.float64]) -> Mat:
        """Every row's position ``(N, n)`` for configurations ``q`` ``(N, dof)`` (finite
        numbers; ``ValueError`` or ``TypeError`` otherwise)."""
        q = check_configurations(q, self.dof, "Table.positions: q", batch=True)
        return row_positions(self.rows, se3.as_configurations(q, self.dof))

    def fk_batch(self, q: NDArray[np.float64]) -> Mat:
        """Poses ``(N, 4, 4)`` of the tool for configurations ``q`` of shape ``(N, dof)`` (large
        batches by the fast path, :mod:`urdf2dh.model._fastfk`); finite numbers only."""
        q = check_configurations(q, self.dof, "Table.fk_batch: q", batch=True)
        return self._fk_batch(q)

    def _fk_batch(self, q: Mat) -> Mat:
        positions = row_positions(self.rows, se3.as_configurations(q, self.dof))
        return chain_fk(*self.link_form(), positions)

    def fk(self, q: NDArray[np.float64]) -> Mat:
        """Pose ``(4, 4)`` of the tool for a configuration ``q`` of shape ``(dof,)``; for a
        stack of shape ``(..., dof)``, poses ``(..., 4, 4)``; finite numbers only."""
        q = check_configurations(q, self.dof, "Table.fk: q")
        return se3.fk_of_stack(self._fk_batch, q, self.dof)

    def joint_frames(self) -> list[Mat]:
        """Home-pose frames ``(4, 4)``: for each joint, the frame whose z axis is its axis (the
        frame just before ``Q_i``: ``B A_1``, ...), then the tool."""
        links = self.link_form()[0]
        out, f = [], np.eye(4)
        for g in links[:-1]:
            f = f @ g
            out.append(f)
        out.append(f @ links[-1])
        return out

    def to_poe(self) -> PoeModel:
        """The equivalent POE model: joint ``i`` moves about the z axis of the frame just before
        ``Q_i``, and ``M`` is the home pose (Sumenkov §III-B; Wu 2019 §II). Its
        :meth:`~urdf2dh.model.poe.PoeModel.size` is the table's (:meth:`PoeModel.sized`), so
        that converting it again decides what the table's conversion decided."""
        poses = self.joint_frames()
        joints = tuple(
            Joint(r.name, r.kind, f[:3, 2].copy(), f[:3, 3].copy(), r.pitch, r.scale, r.lower,
                  r.upper, r.mimic)
            for r, f in zip(self.rows, poses[:-1], strict=True)
        )  # fmt: skip
        return PoeModel(joints, poses[-1], self.robot, self.source, self.base_link,
                        self.tip_link, self.length_unit).sized(self.size)  # fmt: skip

    def _written(self, m: Mat) -> list[list[float]]:
        """A transform's entries as written: round-off (``DEFAULT.written``; times ``size`` for
        the translation) next to 0 or +-1 written as that, no ``-0.0``."""
        within = DEFAULT.written
        out = np.where(np.abs(m) <= within, 0.0, m)
        out[:3, 3] = np.where(np.abs(m[:3, 3]) <= within * self.size, 0.0, m[:3, 3])
        unit = np.abs(np.abs(out[:3, :3]) - 1.0) <= within
        out[:3, :3] = np.where(unit, np.sign(out[:3, :3]), out[:3, :3])
        rows: list[list[float]] = (out + 0.0).tolist()
        return rows

    def _repr_markdown_(self) -> str:
        """In a notebook: the table as ``--format markdown`` writes it (names escaped)."""
        return markdown(self)

    def __str__(self) -> str:
        """The table as a person reads it: ``--format text``."""
        return text(self)

    def __repr__(self) -> str:
        chain = f" ({self.base_link} -> {self.tip_link})" if self.base_link else ""
        return f"<Table {self.convention} of {shown(self.robot)}{visible(chain)}, {self.dof} rows>"

    def to_dataframe(self) -> Any:
        """The table as a ``pandas.DataFrame``: a row each for the base, the joints and the tool,
        the columns of ``--format csv`` (``row``, ``joint``, ``type``, ``pitch``, ``scale``,
        then every parameter, vectors as ``_x``, ``_y``, ``_z``), in radians and the table's
        length unit; a parameter a row does not have is ``NaN``.

        Raises
        ------
        InputError
            pandas is not installed (it is an optional dependency: ``pip install pandas``).
        """
        try:
            import pandas as pd
        except ImportError as e:
            raise missing("Table.to_dataframe", "pandas", "dataframe") from e
        cols = [name for name, _ in flat_columns(self)]
        data = [
            {"row": label, "joint": joint, "type": kind, "pitch": pitch, "scale": scale,
             **{c: params.get(c, np.nan) for c in cols}}
            for label, joint, kind, pitch, scale, params, _ in records(self)
        ]  # fmt: skip
        frame = pd.DataFrame(data, columns=["row", "joint", "type", "pitch", "scale", *cols])
        frame.attrs.update(convention=self.convention, length_unit=self.length_unit)
        return frame

    def to_dict(self) -> dict[str, Any]:
        """The table file tree (what ``--format json`` and ``--format yaml`` write;
        docs/formats/table-file.md)."""
        joints = []
        for r in self.rows:
            entry: dict[str, Any] = {
                "name": r.name, "type": r.kind, "pitch": float(r.pitch),
                "scale": float(r.scale), "params": r.params.to_dict(),
            } | r.file_fields()  # fmt: skip
            joints.append(entry)
        return {
            "schema": SCHEMA,
            "convention": self.convention,
            "robot": self.robot,
            "source": self.source,
            "base_link": self.base_link,
            "tip_link": self.tip_link,
            "units": {"length": self.length_unit, "angle": "rad"},
            "size": float(self.size),
            "base": {"params": self.base.to_dict(), "matrix": self._written(self.base_matrix)},
            "joints": joints,
            "tool": {"params": self.tool.to_dict(), "matrix": self._written(self.tool_matrix)},
            "check": None if self.check is None else {
                "samples": self.check.samples,
                "max_position_error": self.check.max_position_error,
                "max_rotation_error": self.check.max_rotation_error,
                **({"declared_position": self.check.declared_position,
                    "declared_rotation": self.check.declared_rotation}
                   if self.check.declared_position or self.check.declared_rotation else {}),
            },
            "warnings": list(self.warnings),
        }  # fmt: skip
