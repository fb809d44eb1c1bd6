"""Modified (Craig) Denavit-Hartenberg: the standard table's common normals, regrouped.

Forward kinematics of an ``mdh`` table (docs/conventions/mdh.md)::

    T(q) = Rz(theta_B) Tz(d_B) . prod_i [ Rx(alpha_i) Tx(a_i) . Q_i(s_i) . Rz(theta_i) Tz(d_i) ]
           . Rx(alpha_T) Tx(a_T) Rz(theta_T) Tz(d_T)

Row ``i`` holds Craig's ``alpha_{i-1}, a_{i-1}`` (the common normal from the previous axis to
joint ``i``'s) and ``theta_i, d_i`` (along joint ``i``'s axis). These are the same common normals
that the standard convention uses (Wu 2019 §III), grouped around ``Q_i`` the other way: the
standard link ``Rz Tz Rx Tx`` of row ``i`` splits into ``Rz Tz`` (ending Craig's row ``i``) and
``Rx Tx`` (starting Craig's row ``i + 1``). So the modified table is the standard one regrouped,
exact by construction, with the same tolerance judgements and styles.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..geometry import frames
from ..geometry.frames import Frame
from .base import Conversion, Params, Style, angle, length
from .dh import STYLES, RzTz, far_rows, links_from_poe

if TYPE_CHECKING:
    from ..model.poe import PoeModel
    from ..tolerances import Tolerances

__all__ = ["MDH", "CraigLink", "ModifiedDH"]


@dataclass(frozen=True, slots=True)
class CraigLink(Params):
    """A modified D-H row, ``Rx(alpha) Tx(a)`` before the joint and ``Rz(theta) Tz(d)`` after
    it; as the tool, the product ``Rx(alpha) Tx(a) Rz(theta) Tz(d)``."""

    alpha: float = angle()
    a: float = length()
    theta: float = angle()
    d: float = length()

    def around_joint(self) -> tuple[Frame | None, Frame]:
        return frames.rx_tx(self.alpha, self.a), frames.dh_frame(self.theta, self.d, 0.0, 0.0)

    def frame(self) -> Frame:
        return frames.compose(*self.around_joint())  # type: ignore[arg-type]


class ModifiedDH:
    """The ``mdh`` convention."""

    name = "mdh"
    label = "modified D-H (Craig)"
    title = "modified D-H (Craig): Rz Tz . prod[Rx(alpha) Tx(a) Q_i Rz(theta) Tz(d)] . Rx Tx Rz Tz"
    formula = (
        "T(q) = B . prod_i [Rx(alpha_i) Tx(a_i) Rz(q_i + theta_i) Tz(d_i)] . T  "
        "(modified D-H, Craig)"
    )
    base_types: tuple[type[Params], ...] = (RzTz,)
    row_types: tuple[type[Params], ...] = (CraigLink,)
    tool_types: tuple[type[Params], ...] = (CraigLink,)
    styles: tuple[str, ...] = STYLES
    guided = True

    def from_poe(self, model: PoeModel, tol: Tolerances, style: Style) -> Conversion:
        links, (theta, d), judgements = links_from_poe(model, tol, style)
        rows = tuple(
            CraigLink(prev.alpha, prev.a, cur.theta, cur.d)
            for prev, cur in itertools.pairwise(links)
        )
        return Conversion(
            RzTz(links[0].theta, links[0].d),
            rows,
            CraigLink(links[-1].alpha, links[-1].a, theta, d),
            (1.0,) * model.n,
            tuple(judgements),
            far_rows(self.name, model, rows, tol),
        )


MDH = ModifiedDH()
