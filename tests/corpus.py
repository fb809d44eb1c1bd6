"""The hostile-name corpus: robot ``seed`` through every export target and format, judged.

Robot ``seed`` is chain :func:`geometry_of` (``seed``) with :func:`hostile.hostile_names`
(``seed``), written as :func:`kind_of` (``seed``): a URDF, an MJCF file, or a POE file in JSON
or YAML (the names of POE files of even seeds may also hold characters XML cannot carry). Each
run ends in one of

* ``written``: the file is safe (:func:`safety.judge` against the clean twin's file);
* ``refused``: exit 2, one line on stderr naming the problem, no file;

or in a failure: ``traceback`` (an exception escaped, or a temporary file was left),
``internal error``, ``unsafe`` (the file is not its clean twin with the names put in),
``bad refusal`` (another exit code, more than one line, a file left behind),
``unexpected`` (the clean twin was refused but the hostile robot was written).
"""

from __future__ import annotations

import shutil
import tempfile
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from hostile import (
    KINDS,
    RUNS,
    XML_KINDS,
    Names,
    Outcome,
    clean_names,
    hostile_names,
    run,
    write_source,
)
from safety import Unsafe, judge

FAILURES = ("traceback", "internal error", "unsafe", "bad refusal", "unexpected")


@dataclass(frozen=True)
class Verdict:
    seed: int
    kind: str
    run: str  # "export ur", "convert csv", ...
    result: str  # written, refused, or one of FAILURES
    detail: str = ""


def geometry_of(seed: int) -> str:
    return "ur5" if seed % 4 == 1 else "genser6"


def kind_of(seed: int) -> str:
    return KINDS[seed % len(KINDS)]


class Corpus:
    """Runs hostile robots, keeping each clean twin's outcomes (one per chain and kind)."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="urdf2dh-hostile-"))
        self.twins: dict[tuple[str, str], dict[tuple[str, str], Outcome]] = {}
        self.runs = 0

    def close(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)

    def _outcomes(
        self, geometry: str, kind: str, names: Names, label: str, runs: list[tuple[str, str]] = RUNS
    ) -> dict[tuple[str, str], Outcome]:
        directory = self.root / label
        directory.mkdir()
        try:
            source = write_source(directory, geometry, names, kind)
            return {(c, w): run(directory, source, c, w, names, kind) for c, w in runs}
        finally:
            shutil.rmtree(directory, ignore_errors=True)

    def twin(self, geometry: str, kind: str) -> dict[tuple[str, str], Outcome]:
        if (geometry, kind) not in self.twins:
            self.twins[geometry, kind] = self._outcomes(
                geometry, kind, clean_names(geometry), f"clean-{geometry}-{kind}"
            )
        return self.twins[geometry, kind]

    def check(
        self,
        names: Names,
        geometry: str,
        kind: str,
        runs: list[tuple[str, str]] = RUNS,
        seed: int = -1,
    ) -> list[Verdict]:
        """Run ``names`` on chain ``geometry`` written as ``kind`` and judge every run."""
        shown = dict(
            zip(clean_names(geometry).shown(kind).keys(), names.shown(kind).values(), strict=True)
        )
        twin = self.twin(geometry, kind)
        self.runs += 1
        outcomes = self._outcomes(geometry, kind, names, f"robot-{self.runs}", runs)
        return [
            Verdict(seed, kind, f"{c} {w}", *_verdict(w, outcomes[c, w], twin[c, w], shown))
            for c, w in runs
        ]

    def robot(self, seed: int) -> list[Verdict]:
        """Hostile robot ``seed`` (POE files of even seeds may hold control characters)."""
        geometry, kind = geometry_of(seed), kind_of(seed)
        names = hostile_names(seed, geometry, controls=kind not in XML_KINDS and seed % 2 == 0)
        return self.check(names, geometry, kind, seed=seed)


def _verdict(what: str, got: Outcome, clean: Outcome, names: dict[str, str]) -> tuple[str, str]:
    if got.crashed is not None:
        return "traceback", got.crashed
    if "internal error" in got.stderr or "Traceback" in got.stderr:
        return "internal error", got.stderr.strip()
    if got.code != 0:
        lines = got.stderr.splitlines()
        if (
            got.code != 2
            or len(lines) != 1
            or not lines[0].startswith("urdf2dh: error: ")
            or got.output is not None
        ):
            return "bad refusal", f"exit {got.code}: {got.stderr!r}"
        return "refused", lines[0]
    if got.output is None:
        return "bad refusal", "exit 0 without a file"
    if clean.output is None:
        return "unexpected", f"the clean twin was refused: {clean.stderr.strip()}"
    try:
        judge(what, got.output, clean.output, names)
    except Unsafe as e:
        return "unsafe", str(e)
    return "written", ""


def tally(verdicts: list[Verdict]) -> Counter[str]:
    return Counter(v.result for v in verdicts)
