"""How many kinematic parameters of a chain measurements can identify (Wu 2019 §V).

The parameters a calibration can tell apart, per joint: its line (a revolute joint's 4: two
turns and two shifts of the line; a helical joint's 5: and its pitch; a prismatic joint's 2:
its direction, its location being free) and its scale (1); and 6 for the placement of the base
and the tool, of which 4 sit in the base transform and 2 in the tool (§V-B, Fig. 3). So, for a
chain of ``h`` helical, ``r`` revolute and ``t`` prismatic joints, ``n`` in all:

* ``maximum``, eq. (23): ``5h + 4r + 2t + n + 6`` (lines, scales, base and tool);
* ``conventional``, eq. (22): ``4r + 2t + 6``, helical joints counted as revolute (the
  conventional setting leaves out helices and scale factors, §V-A).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass

__all__ = ["BASE", "LINE_PARAMETERS", "PLACEMENT", "SYMBOLS", "TOOL", "Identifiability"]

#: Parameters of a joint's line, by kind.
LINE_PARAMETERS = {"helical": 5, "revolute": 4, "prismatic": 2}
#: Wu's symbols for the numbers of joints of each kind.
SYMBOLS = {"helical": "h", "revolute": "r", "prismatic": "t"}
#: Parameters of the base and tool placement; of them, those in the base and in the tool.
PLACEMENT, BASE, TOOL = 6, 4, 2


@dataclass(frozen=True, slots=True)
class Identifiability:
    """The parameter counts of a chain (module docstring)."""

    helical: int
    revolute: int
    prismatic: int

    @classmethod
    def of(cls, kinds: Iterable[str]) -> Identifiability:
        """The counts of a chain whose joints are of these kinds."""
        count = Counter(kinds)
        return cls(count["helical"], count["revolute"], count["prismatic"])

    @property
    def joints(self) -> int:
        """``n``."""
        return self.helical + self.revolute + self.prismatic

    @property
    def maximum(self) -> int:
        """Wu 2019 eq. (23): ``5h + 4r + 2t + n + 6``."""
        lines = sum(LINE_PARAMETERS[k] * getattr(self, k) for k in LINE_PARAMETERS)
        return int(lines) + self.joints + PLACEMENT

    @property
    def conventional(self) -> int:
        """Wu 2019 eq. (22): ``4r + 2t + 6``, helical joints counted as revolute."""
        revolute = LINE_PARAMETERS["revolute"] * (self.revolute + self.helical)
        return revolute + LINE_PARAMETERS["prismatic"] * self.prismatic + PLACEMENT
