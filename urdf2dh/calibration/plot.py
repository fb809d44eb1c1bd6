"""Pictures of a calibration (``calibrate --plot FILE``): PNG through matplotlib, or one
self-contained interactive HTML page through plotly, written as every urdf2dh page is
(:func:`urdf2dh.emit.html.offline_page`: plotly.js in the page, nothing fetched when it is
opened, every name written with :func:`~urdf2dh.escape.html_text`).

Three panels:

* each configuration's RMS position error before (the nominal joints with base and tool fitted)
  and after, fitted and held-out or validation configurations apart;
* the distribution of those errors, before and after;
* the largest changes of the joints' parameters from the nominal's (base and tool fitted), each
  as how far it moves a measured tool point at most (so that angles, lengths and scales share one
  axis), with the same for one standard deviation as its error bar (none at the base-tool level).
"""

from __future__ import annotations

import io
from typing import TYPE_CHECKING, Any

from ..emit.html import offline_page, plotly_objects
from ..emit.picture import matplotlib_figure
from ..errors import UsageError
from ..escape import html_text, matplotlib_text

if TYPE_CHECKING:
    from .result import Calibration

__all__ = ["FORMATS", "LARGEST", "plot_calibration"]

FORMATS = ("png", "html", "htm")
LARGEST = 12  # parameter changes drawn
_SET = {"fit": "fitted", "held_out": "held out", "validation": "validation"}


def _panels(cal: Calibration) -> dict[str, Any]:
    """What the panels draw, in the calibration's (its user's) length unit."""
    unit = cal.units.length
    joints = {j.name for j in cal.nominal.joints}
    params = [p for p in cal.parameters if p.name.rsplit(".", 1)[0] in joints]
    params = sorted(params, key=lambda p: -p.effect)[:LARGEST][::-1]
    spread = []
    for p in params:
        reach = p.effect / abs(p.change) if p.change else 0.0
        spread.append(0.0 if p.std is None else p.std * reach)
    return {
        "unit": unit,
        "sets": [
            (
                _SET[c.name],
                list(c.configurations),
                list(c.before_position),
                list(c.after_position),
            )
            for c in cal.comparisons
        ],
        "names": [p.name for p in params],
        "effects": [p.effect for p in params],
        "spread": spread,
        "title": (
            f"{cal.nominal.name}: {cal.level} level, {cal.counts.parameters} parameters, "
            f"{cal.counts.configurations} configurations"
        ),
    }


def _png(cal: Calibration) -> bytes:
    Figure, FigureCanvasAgg = matplotlib_figure("the calibration's picture")
    d = _panels(cal)
    unit = matplotlib_text(d["unit"])
    fig = Figure(figsize=(13, 4.6), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2, ax3 = fig.subplots(1, 3, width_ratios=(2.2, 1.2, 1.6))
    for label, configs, before, after in d["sets"]:
        ax1.plot(configs, before, "o", mfc="none", label=f"before, {label}")
        ax1.plot(configs, after, "s", label=f"after, {label}")
    ax1.set_xlabel("configuration")
    ax1.set_ylabel(f"RMS position error ({unit})")
    ax1.set_yscale("log")
    ax1.legend(fontsize=8)
    ax1.set_title("per configuration")
    before_all = [x for s in d["sets"] for x in s[2]]
    after_all = [x for s in d["sets"] for x in s[3]]
    top = max([*before_all, *after_all, 1e-300])
    bins = [top * i / 24 for i in range(25)]
    ax2.hist(before_all, bins=bins, alpha=0.6, label="before")
    ax2.hist(after_all, bins=bins, alpha=0.6, label="after")
    ax2.set_xlabel(f"RMS position error ({unit})")
    ax2.set_ylabel("configurations")
    ax2.legend(fontsize=8)
    ax2.set_title("distribution")
    positions = range(len(d["names"]))
    ax3.barh(positions, d["effects"], xerr=d["spread"], color="tab:green", alpha=0.8)
    ax3.set_yticks(list(positions), [matplotlib_text(n) for n in d["names"]], fontsize=7)
    ax3.set_xlabel(f"change at the tool ({unit}), bar: 1 std")
    ax3.set_title("largest parameter changes")
    fig.suptitle(matplotlib_text(d["title"]))
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return buf.getvalue()


def _html(cal: Calibration) -> bytes:
    go = plotly_objects("the calibration's interactive page")
    from plotly.subplots import make_subplots

    d = _panels(cal)
    unit = html_text(d["unit"])
    fig = make_subplots(
        rows=1,
        cols=3,
        column_widths=[0.45, 0.22, 0.33],
        subplot_titles=("per configuration", "distribution", "largest parameter changes"),
    )
    for label, configs, before, after in d["sets"]:
        fig.add_trace(
            go.Scatter(x=configs, y=before, mode="markers", name=f"before, {label}"), 1, 1
        )
        fig.add_trace(go.Scatter(x=configs, y=after, mode="markers", name=f"after, {label}"), 1, 1)
    before_all = [x for s in d["sets"] for x in s[2]]
    after_all = [x for s in d["sets"] for x in s[3]]
    fig.add_trace(go.Histogram(x=before_all, name="before", opacity=0.6), 1, 2)
    fig.add_trace(go.Histogram(x=after_all, name="after", opacity=0.6), 1, 2)
    fig.add_trace(
        go.Bar(
            x=d["effects"],
            y=[html_text(n) for n in d["names"]],
            orientation="h",
            error_x={"type": "data", "array": d["spread"]},
            name="change at the tool",
        ),
        1,
        3,
    )
    fig.update_yaxes(type="log", title_text=f"RMS position error ({unit})", row=1, col=1)
    fig.update_xaxes(title_text="configuration", row=1, col=1)
    fig.update_xaxes(title_text=f"RMS position error ({unit})", row=1, col=2)
    fig.update_xaxes(title_text=f"change at the tool ({unit})", row=1, col=3)
    fig.update_layout(title_text=html_text(d["title"]), barmode="overlay")
    return offline_page(fig, d["title"]).encode("utf-8")


def plot_calibration(cal: Calibration, fmt: str) -> bytes:
    """The calibration's pictures as ``png`` or ``html`` bytes (module docstring)."""
    if fmt not in FORMATS:
        raise UsageError(f"unknown picture format '{fmt}'; valid: png, html")
    return _png(cal) if fmt == "png" else _html(cal)
