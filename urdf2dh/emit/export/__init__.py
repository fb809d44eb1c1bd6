"""Controller and toolbox configuration files, each generated from a checked table.

One module per target; :func:`export` is the entry point. Every target starts from
:func:`~urdf2dh.conventions.convert.to_table` (so from a table whose forward kinematics was measured
against the source) and only formats its parameters, or refuses the chain with the reason
(:class:`~urdf2dh.errors.ExportError`, exit 2).

=================  ====================================================  ===========  ========
target             file                                                  conventions  style
=================  ====================================================  ===========  ========
``ur``             UR ``default_kinematics.yaml`` (+ calibration hash)   dh           ur
``linuxcnc``       LinuxCNC ``genserkins`` HAL ``setp`` lines            mdh          zero
``rtb``            roboticstoolbox-python ``DHRobot`` script             dh, mdh      any
``matlab``         Robotics System Toolbox ``rigidBodyTree`` script      dh, mdh      any
``kdl``            PyKDL ``Chain`` script                                dh, mdh      any
``corke-matlab``   Peter Corke's MATLAB toolbox ``SerialLink`` script    dh, mdh      any
``opw``            OPW kinematics parameters (``opw_kinematics`` YAML)   (POE model)  -
``eaik``           EAIK ``HomogeneousRobot`` script (analytic IK)        dh           wu
``ikdh``           ikdh robot file (Husty-Pfurner general 6R IK)         dh           any
=================  ====================================================  ===========  ========

The first convention and style listed are the defaults. ``opw`` reads the POE model itself (its
parameters come from the axis lines, :mod:`urdf2dh.conventions.opw`), so it takes no convention or
style.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ...errors import UsageError, choices, near

if TYPE_CHECKING:
    from ...conventions.table import Table
    from ...model.poe import PoeModel
    from .common import ExportOptions

__all__ = ["TARGETS", "ExportOptions", "Target", "export", "export_table", "table_choices"]


def __getattr__(name: str) -> Any:
    # ExportOptions lives with the targets' shared helpers (numpy); the command line's --help reads
    # TARGETS only
    if name == "ExportOptions":
        from .common import ExportOptions

        return ExportOptions
    raise AttributeError(f"module 'urdf2dh.emit.export' has no attribute {name!r}")


@dataclass(frozen=True, slots=True)
class Target:
    """An export target: its module, what it writes, and the tables it reads."""

    name: str
    module: str
    summary: str
    conventions: tuple[str, ...]
    styles: tuple[str, ...]
    suffix: str

    @property
    def reads_model(self) -> bool:
        """Whether the target is written from the POE model rather than from a table."""
        return not self.conventions

    def render(self, table: Table, opts: ExportOptions) -> str:
        mod = importlib.import_module(f"urdf2dh.emit.export.{self.module}")
        return str(mod.render(table, opts))

    def render_model(self, model: PoeModel, opts: ExportOptions, samples: int | None = None) -> str:
        mod = importlib.import_module(f"urdf2dh.emit.export.{self.module}")
        return str(mod.render_model(model, opts, samples))


TARGETS: dict[str, Target] = {
    t.name: t
    for t in [
        Target(
            "ur",
            "ur",
            "Universal Robots default_kinematics.yaml with calibration hash",
            ("dh",),
            ("ur",),
            ".yaml",
        ),
        Target(
            "linuxcnc",
            "linuxcnc",
            "LinuxCNC genserkins HAL parameters (Craig D-H)",
            ("mdh",),
            ("zero", "ur", "wu"),
            ".hal",
        ),
        Target(
            "rtb",
            "rtb",
            "roboticstoolbox-python DHRobot script (hayati: an ETS Robot)",
            ("dh", "mdh", "hayati"),
            ("wu", "ur", "zero"),
            ".py",
        ),
        Target(
            "matlab",
            "matlab",
            "MATLAB Robotics System Toolbox rigidBodyTree script",
            ("dh", "mdh"),
            ("wu", "ur", "zero"),
            ".m",
        ),
        Target(
            "kdl",
            "kdl",
            "PyKDL Chain script (Frame.DH / Frame.DH_Craig1989)",
            ("dh", "mdh"),
            ("wu", "ur", "zero"),
            ".py",
        ),
        Target(
            "corke-matlab",
            "corke_matlab",
            "Peter Corke's MATLAB Robotics Toolbox SerialLink script",
            ("dh", "mdh"),
            ("wu", "ur", "zero"),
            ".m",
        ),
        Target(
            "opw",
            "opw",
            "OPW kinematics parameters (opw_kinematics, rs-opw-kinematics YAML)",
            (),
            (),
            ".yaml",
        ),
        Target(
            "eaik",
            "eaik",
            "EAIK HomogeneousRobot script: analytic IK, every branch",
            ("dh",),
            ("wu",),
            ".py",
        ),
        Target(
            "ikdh",
            "ikdh",
            "ikdh robot file: Husty-Pfurner general 6R IK (mm; base and tool beside)",
            ("dh",),
            ("wu", "ur", "zero"),
            ".yaml",
        ),
    ]
}


def _target(name: str) -> Target:
    if name not in TARGETS:
        raise UsageError(
            f"unknown export target '{name}'{near(name, TARGETS)}; valid: {choices(TARGETS)}"
        )
    return TARGETS[name]


def table_choices(target: str, convention: str | None, style: str | None) -> tuple[str, str]:
    """The convention and style a target's table is built with (its defaults where ``None``;
    empty for a target that reads the POE model, which takes neither). A convention the target
    does not read is refused by the target itself, once the table is made, naming its first row
    of a form the target has no place for (:func:`.common.require_convention`)."""
    t = _target(target)
    if t.reads_model:
        if convention or style:
            raise UsageError(
                f"export target {target} is written from the POE model; it takes no convention "
                "or style"
            )
        return "", ""
    convention = convention or t.conventions[0]
    style = style or t.styles[0]
    if style not in t.styles:
        raise UsageError(f"export target {target} takes style {' or '.join(t.styles)}, not {style}")
    return convention, style


def export_table(table: Table, target: str, opts: ExportOptions | None = None) -> str:
    """Render an already checked table for ``target``."""
    from .common import ExportOptions

    return _target(target).render(table, opts or ExportOptions())


def export(
    model: PoeModel,
    target: str,
    convention: str | None = None,
    style: str | None = None,
    opts: ExportOptions | None = None,
    samples: int | None = 1000,
) -> str:
    """A controller's or toolbox's file for ``model``: converted, checked and rendered.

    Parameters
    ----------
    model
        The robot (:func:`urdf2dh.load`).
    target
        A name in :data:`TARGETS` (``ur``, ``linuxcnc``, ``rtb``, ``matlab``, ``kdl``,
        ``corke-matlab``, ``opw``, ``eaik``, ``ikdh``).
    convention, style
        The table the target reads (``None``: the target's own, D-H for every target that reads
        a table, unless a D-H table is not the one to write,
        :mod:`urdf2dh.conventions.choice`: then the target's ``hayati`` table where it reads one,
        else the D-H table with the reason among its warnings where it is exact, and an
        :class:`~urdf2dh.errors.ExportError` saying why where it is not).
    opts
        The length unit of targets that fix one, and the tolerances (:class:`ExportOptions`).
    samples
        Configurations of the table's (or OPW's) self-check, ``None`` for its default.

    Returns
    -------
    str
        The file's text.

    Raises
    ------
    TypeError, ValueError
        Arguments as :func:`urdf2dh.to_table` checks them.
    UsageError
        An unknown target, convention or style, or one the target cannot take.
    ExportError
        A model the target cannot represent (the message says why), or (``convention=None``)
        one whose D-H table deviates beyond what was asked, for a target that reads no other.
    ConversionError
        The table failed its self-check.
    """
    from ...checks import check_count, check_instance
    from ...conventions.choice import FALLBACK, choose
    from ...conventions.convert import to_table
    from ...errors import ExportError, Remedy
    from ...model.poe import PoeModel
    from .common import ExportOptions

    check_instance(model, PoeModel, "export: model", "urdf2dh.load(SOURCE) reads one")
    check_instance(target, str, "export: target")
    if samples is not None:
        check_count(samples, "export: samples")
    opts = ExportOptions() if opts is None else check_instance(opts, ExportOptions, "export: opts")
    asked = convention
    convention, style = table_choices(target, convention, style)
    t = _target(target)
    if t.reads_model:
        return t.render_model(model, opts, samples)
    fallback = FALLBACK if asked is None and FALLBACK in t.conventions else None
    if asked is not None:
        table = to_table(model, convention, opts.tol, samples=samples, style=style)
        return export_table(table, target, opts)
    chosen = choose(model, convention, opts.tol, samples, style, fallback)
    if chosen.objection is not None and not chosen.objection.exact and fallback is None:
        raise ExportError(
            f"export target {target} reads {' and '.join(t.conventions)} tables, and "
            f"{chosen.objection.reason}",
            remedy=Remedy("convention", "; {} writes it all the same", convention),
        )
    return export_table(chosen.table, target, opts)
