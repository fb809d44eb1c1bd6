"""Measuring helpers for ``benchmarks/run.py``: best-of timing, new processes with their own peak
memory, import times, and the printed table.

Times are the best of several runs (the least disturbed estimate of a cost on a shared machine);
competing measurements are interleaved, so that both sides see the same disturbances.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
import tracemalloc
from collections.abc import Callable, Sequence
from dataclasses import dataclass

__all__ = [
    "Figure",
    "Process",
    "best_of",
    "import_ms",
    "paired",
    "peak_alloc",
    "print_table",
    "run_process",
]


def best_of(fns: Sequence[Callable[[], object]], repeat: int, number: int = 1) -> list[float]:
    """Best seconds per call of each function over ``repeat`` interleaved rounds of ``number``
    calls (one untimed warm-up call each first)."""
    for fn in fns:
        fn()
    best = [float("inf")] * len(fns)
    for _ in range(repeat):
        for k, fn in enumerate(fns):
            t0 = time.perf_counter()
            for _ in range(number):
                fn()
            best[k] = min(best[k], (time.perf_counter() - t0) / number)
    return best


def peak_alloc(fn: Callable[[], object]) -> float:
    """Peak bytes allocated through Python's and numpy's allocators while ``fn`` runs."""
    tracemalloc.start()
    try:
        fn()
        return float(tracemalloc.get_traced_memory()[1])
    finally:
        tracemalloc.stop()


@dataclass(frozen=True)
class Process:
    """A finished new process: best wall time and best CPU time (user + system) over the runs,
    and its peak resident memory."""

    seconds: float
    peak_bytes: float
    stdout: str
    cpu: float = 0.0


# Runs the command from a small Python process: a child's peak resident memory (ru_maxrss) counts
# its parent's at the fork, and this benchmark's own process holds hundreds of MiB.
LAUNCHER = """
import json, os, subprocess, sys, tempfile, time
command, runs = json.loads(sys.argv[1]), int(sys.argv[2])
best, cpu, peak = float("inf"), float("inf"), 0
for _ in range(runs):
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(command, stdout=out, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)
        best = min(best, time.perf_counter() - t0)
        cpu = min(cpu, usage.ru_utime + usage.ru_stime)
        proc.returncode = os.waitstatus_to_exitcode(status)
        peak = max(peak, usage.ru_maxrss * 1024)  # Linux: KiB
        out.seek(0), err.seek(0)
        result = {"seconds": best, "cpu": cpu, "peak": peak, "stdout": out.read().decode(),
                  "stderr": err.read().decode(), "code": proc.returncode}
        if proc.returncode:
            break
print(json.dumps(result))
"""


def run_process(args: Sequence[str], runs: int) -> Process:
    """Run ``python args...`` ``runs`` times (it must exit 0): best wall time, peak memory."""
    launched = subprocess.run(
        [sys.executable, "-c", LAUNCHER, json.dumps([sys.executable, *args]), str(runs)],
        capture_output=True,
        text=True,
        check=True,
    )
    result = json.loads(launched.stdout)
    if result["code"] != 0:
        raise RuntimeError(
            f"python {' '.join(args)} exited {result['code']}: {result['stderr'].strip()}"
        )
    return Process(result["seconds"], float(result["peak"]), result["stdout"], result["cpu"])


def paired(commands: Sequence[Sequence[str]], runs: int) -> list[Process]:
    """Each of ``python args...`` run ``runs`` times, the commands taking turns (so that each
    sees the machine's load as the others do): the median wall and CPU times, the largest peak
    memory."""
    results: list[list[Process]] = [[] for _ in commands]
    for _ in range(runs):
        for out, args in zip(results, commands, strict=True):
            out.append(run_process(args, 1))
    return [
        Process(
            statistics.median(p.seconds for p in out),
            max(p.peak_bytes for p in out),
            out[-1].stdout,
            statistics.median(p.cpu for p in out),
        )
        for out in results
    ]


def import_ms(statement: str) -> dict[str, float]:
    """Milliseconds each top-level module imported by ``statement`` took (``-X importtime``,
    cumulative), plus ``"total"``, in a new process."""
    proc = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", statement],
        capture_output=True,
        text=True,
        check=True,
    )
    out: dict[str, float] = {"total": 0.0}
    for line in proc.stderr.splitlines():
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _, cumulative, name = line[len("import time:") :].split("|")
        if name.startswith("  "):  # nested: counted in its top-level importer
            continue
        out[name.strip()] = int(cumulative) / 1000.0
        out["total"] += int(cumulative) / 1000.0
    return out


@dataclass(frozen=True)
class Figure:
    """One row of the report: our figure, Pinocchio's counterpart, and the goal on their ratio
    (ours / Pinocchio's) or on ours alone."""

    name: str
    ours: float
    pinocchio: float
    unit: str
    goal: str = ""
    met: bool | None = None

    @property
    def ratio(self) -> float:
        return self.ours / self.pinocchio


SCALE = {"s": 1.0, "ms": 1e3, "us": 1e6, "MiB": 1.0 / 2**20}


def print_table(title: str, rows: Sequence[Figure]) -> None:
    """A Markdown table: figure | ours | Pinocchio | ratio | goal."""
    print(f"\n### {title}\n")
    print("| figure | ours | Pinocchio | ratio | goal |")
    print("|---|---:|---:|---:|---|")
    for f in rows:
        k = SCALE[f.unit]
        goal = f.goal + ("" if f.met is None else (" (met)" if f.met else " (NOT met)"))
        print(
            f"| {f.name} | {f.ours * k:.4g} {f.unit} | {f.pinocchio * k:.4g} {f.unit} | "
            f"{f.ratio:.3g}x | {goal} |"
        )
    sys.stdout.flush()
