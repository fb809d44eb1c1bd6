"""A seeded corpus of mutated real URDFs, each run through ``urdf2dh convert`` and ``verify``.

    python scripts/fuzz_urdf.py                    # the whole corpus: 600 mutations, seed 0
    python scripts/fuzz_urdf.py --count 50 --seed 3

The originals are the URDF arms urdf2dh bundles (example-robot-data's and ``robots/``) and the
URDFs under ``tests/data``. Each case applies one to three seeded mutations (``mutations.py``)
and runs both commands in-process through ``urdf2dh.cli.main``. Every case must hold:

- no traceback and no "internal error"; exit codes 0, 1 or 2 only;
- a failing command writes one line, ``urdf2dh: error: ...``, naming the file;
- no Python warning (numpy's RuntimeWarning included) is raised;
- a table that converts agrees with Pinocchio within its declared bound: whenever ``convert``
  exits 0, ``verify`` exits 0, unless Pinocchio itself cannot load the file.

The script prints the cases by outcome and mutation kind, then every broken case; it exits 1 if
any case broke an invariant.
"""

from __future__ import annotations

import contextlib
import io
import re
import sys
import tempfile
import warnings
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from corpus_main import corpus_main
from mutations import MUTATIONS, Original, mutate

from urdf2dh.check.verify import native_stderr
from urdf2dh.cli import main as cli
from urdf2dh.io.catalog import ERD, OURS, ROBOTS, robot_path
from urdf2dh.io.urdf import load_tree

ROOT = Path(__file__).resolve().parents[1]
PINOCCHIO_REFUSES = "Pinocchio cannot load it"
VERIFY_SAMPLES = "200"


@dataclass(frozen=True, slots=True)
class Run:
    """One command on one case: exit code, what it wrote, the warnings it raised."""

    code: int
    out: str
    err: str
    warned: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Outcome:
    """A case and what the two commands made of it."""

    index: int
    kinds: tuple[str, ...]
    description: str
    convert: Run
    verify: Run
    problems: tuple[str, ...]
    pinocchio_loads: bool | None  # for a refused file: does Pinocchio load it (None: not asked)

    @property
    def label(self) -> str:
        """``converted``, ``refused (exit 2)``, ... and what verify said."""
        names = {0: "converted", 1: "self-check refused", 2: "input error"}
        convert = names.get(self.convert.code, f"exit {self.convert.code}")
        if self.verify.code == 0:
            verify = "Pinocchio agrees"
        elif PINOCCHIO_REFUSES in self.verify.err:
            verify = "Pinocchio cannot load it"
        elif self.verify.code == 1 and self.verify.err.startswith("verify: FAILED"):
            verify = "DISAGREES with Pinocchio"
        else:
            verify = names.get(self.verify.code, f"exit {self.verify.code}")
        return f"convert: {convert}; verify: {verify}"


def originals() -> list[Original]:
    """The bundled URDF arms and ``tests/data``'s URDFs, with their base and tip links."""
    out = []
    for bundled in ROBOTS.values():
        if bundled.file.startswith((ERD, OURS)) and bundled.file.endswith(".urdf"):
            path = robot_path(bundled)
            out.append(_original(bundled.name, path, bundled.base, bundled.tip))
    for path in sorted((ROOT / "tests" / "data").glob("*.urdf")):
        out.append(_original(path.stem, path, None, None))
    return out


def _original(name: str, path: Path, base: str | None, tip: str | None) -> Original:
    tree = load_tree(path)
    chain = tree.chain(base or tree.root, tip or tree.default_tip(base or tree.root))
    return Original(name, path.read_text(encoding="utf-8"), base, tip, tuple(j.name for j in chain))


def _command(argv: list[str]) -> Run:
    """``urdf2dh ARGV`` in this process: its output captured (what C++ code writes to file
    descriptor 2 as well, after Python's), and every warning recorded."""
    out, err = io.StringIO(), io.StringIO()
    with (
        native_stderr() as native,
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
        warnings.catch_warnings(record=True) as caught,
    ):
        warnings.simplefilter("always")
        try:
            code = cli(argv)
        except SystemExit as e:  # argparse: a usage error
            code = e.code if isinstance(e.code, int) else 2
    return Run(
        code,
        out.getvalue(),
        err.getvalue() + "".join(f"{line}\n" for line in native),
        tuple(f"{w.category.__name__}: {w.message}" for w in caught),
    )


def _problems(path: Path, convert: Run, verify: Run) -> list[str]:
    """The invariants (module docstring) this case breaks."""
    problems = []
    for name, run in (("convert", convert), ("verify", verify)):
        text = run.out + run.err
        if "Traceback" in text:
            problems.append(f"{name}: traceback")
        if "internal error" in text:
            problems.append(f"{name}: internal error: {run.err.strip()}")
        if run.code not in (0, 1, 2):
            problems.append(f"{name}: exit code {run.code}")
        if run.warned:
            problems.append(f"{name}: warning {run.warned[0]}")
        failed_verify = name == "verify" and run.code == 1 and run.err.startswith("verify:")
        if run.code != 0 and not failed_verify:
            lines = run.err.splitlines()
            if len(lines) != 1 or not lines[0].startswith("urdf2dh: error: "):
                problems.append(f"{name}: error is not one line: {run.err!r}")
            elif str(path) not in lines[0]:
                problems.append(f"{name}: error does not name the file: {lines[0]}")
    if convert.code == 0 and verify.code != 0 and PINOCCHIO_REFUSES not in verify.err:
        problems.append(
            f"converted, yet verify exits {verify.code}: "
            f"{(verify.err or verify.out).strip()[-300:]}"
        )
    return problems


def run_case(index: int, original: Original, rng: np.random.Generator, directory: Path) -> Outcome:
    """Mutate ``original`` (seeded by ``rng``) and run both commands on the result."""
    kinds, description, data = mutate(original, rng)
    path = directory / f"case{index}.urdf"
    path.write_bytes(data)
    chain = [
        *(["--base", original.base] if original.base else []),
        *(["--tip", original.tip] if original.tip else []),
    ]
    output = directory / f"case{index}.json"
    convert = _command(["convert", str(path), *chain, "-o", str(output)])
    output.unlink(missing_ok=True)
    verify = _command(["verify", str(path), *chain, "--samples", VERIFY_SAMPLES])
    loads = _pinocchio_loads(path) if convert.code == 2 else None
    problems = tuple(_problems(path, convert, verify))
    return Outcome(index, kinds, description, convert, verify, problems, loads)


def _pinocchio_loads(path: Path) -> bool:
    """Whether Pinocchio builds a model from the file as it stands (its complaints silenced)."""
    import pinocchio

    with native_stderr():
        try:
            pinocchio.buildModelFromUrdf(str(path))
        except Exception:  # RuntimeError, ValueError with urdfdom's text
            return False
    return True


def run_corpus(count: int, seed: int) -> list[Outcome]:
    """``count`` seeded cases over the originals, in turn."""
    rng = np.random.default_rng(seed)
    sources = originals()
    outcomes = []
    with tempfile.TemporaryDirectory(prefix="urdf2dh-fuzz-") as tmp:
        for index in range(count):
            outcomes.append(run_case(index, sources[index % len(sources)], rng, Path(tmp)))
    return outcomes


def report(outcomes: list[Outcome]) -> str:
    """Counts by outcome and by mutation kind, then every case that broke an invariant."""
    lines = [f"{len(outcomes)} mutated URDFs, each through convert and verify", "", "By outcome:"]
    for label, n in Counter(o.label for o in outcomes).most_common():
        lines.append(f"  {n:5d}  {label}")
    lines += ["", "By mutation kind (a case may apply several):"]
    kinds = Counter(k for o in outcomes for k in o.kinds)
    for kind in MUTATIONS:
        refused = sum(1 for o in outcomes if kind in o.kinds and o.convert.code == 2)
        lines.append(f"  {kinds[kind]:5d}  {kind:<22} ({refused} refused as input errors)")
    stricter = Counter(_kind_of(o.convert.err) for o in outcomes if o.pinocchio_loads)
    lines += ["", f"Refused although Pinocchio loads the file: {sum(stricter.values())}, for"]
    lines += [f"  {n:5d}  {kind}" for kind, n in stricter.most_common()]
    broken = [o for o in outcomes if o.problems]
    lines += ["", f"Cases that broke an invariant: {len(broken)}"]
    for o in broken:
        lines.append(f"  case {o.index} ({o.description}): " + "; ".join(o.problems))
    return "\n".join(lines)


def _kind_of(error: str) -> str:
    """An error message without the file, names and values: the kind of fault it reports."""
    text = error.strip().removeprefix("urdf2dh: error: ").split(".urdf: ", 1)[-1]
    text = re.sub(r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\"", "'.'", text)
    return re.sub(r"\[.*\]|[-+]?[0-9][0-9.e+-]*", "#", text)[:110]


def main(argv: list[str] | None = None) -> int:
    return corpus_main(__doc__, run_corpus, report, 600, argv)


if __name__ == "__main__":
    sys.exit(main())
