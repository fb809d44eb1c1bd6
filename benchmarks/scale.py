"""Chain length: conversion time and FK accuracy of random chains from 10 to 2,000 joints, beside
Pinocchio's model build and Pinocchio's own FK accuracy (part of ``benchmarks/run.py``)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pinocchio as pin
from chains import random_chain_urdf  # tests/chains.py: seeded random URDF chains
from reference import chain_fk
from timing import Figure, best_of, peak_alloc, run_process

from urdf2dh.check.verify import pinocchio_fk
from urdf2dh.conventions import NAMES as CONVENTIONS
from urdf2dh.conventions.convert import to_table
from urdf2dh.geometry.se3 import pose_errors
from urdf2dh.io.sources import Source
from urdf2dh.io.urdf import tree_to_poe
from urdf2dh.io.urdf.parse import document, parse_xml, yourdfpy_robot
from urdf2dh.io.urdf.tree import UrdfTree, build_tree
from urdf2dh.io.urdf.validate import check_robot
from urdf2dh.tolerances import JOINTS

__all__ = ["PIN_FK_MAX", "at_the_bounds", "chain_lengths"]

PIN_FK_MAX = 200  # Pinocchio beyond its Data's size (verify.DATA_JOINTS) runs joint by joint: slow

GOAL_SECONDS, GOAL_BYTES = 15.0, 2 * 2**30  # convert at the bound; verify of 1,000 joints: 1 GiB
VERIFY_GOAL_BYTES = 2**30


def _tree(data: bytes, robot: object) -> UrdfTree:
    """parse_tree's own part: one XML parse, our strict check, the tree from yourdfpy's Robot."""
    xml = document(data, "chain.urdf")
    check_robot(parse_xml(xml, "chain.urdf"), "chain.urdf")
    return build_tree(robot, "chain.urdf", xml)


def chain_lengths(sizes: list[int], accuracy_samples: int) -> tuple[list[Figure], list[str]]:
    """Random chains (tests/chains.py): our parse and checks of the URDF text, the tree, chain
    walk, dh and self-check (yourdfpy's Robot made apart) vs buildModelFromXML, and the worst FK
    error of every convention (and of Pinocchio) against an extended-precision FK."""
    rows, times, errors, lines, loads = [], [], [], [], []
    for n in sizes:
        text, _ = random_chain_urdf(n, n)
        data = text.encode()
        t0 = time.perf_counter()
        robot = yourdfpy_robot(parse_xml(data, "chain.urdf"), "chain.urdf")
        loads.append(f"{n}: {time.perf_counter() - t0:.3g} s")

        def ours(data: bytes = data, robot: object = robot) -> object:
            tree = _tree(data, robot)  # as parse_tree, yourdfpy's part made once above
            return to_table(tree_to_poe(tree, "base", "tool"), "dh")

        repeat = 5 if n <= 200 else 2
        pin_t, t = best_of([lambda text=text: pin.buildModelFromXML(text), ours], repeat)
        times.append(t)
        ok = t <= 1.0 if n == 1000 else None
        rows.append(
            Figure(
                f"{n} joints: convert to dh, self-check included",
                t,
                pin_t,
                "ms",
                "ours <= 1 s" if n == 1000 else "",
                ok,
            )
        )
        tree = _tree(data, robot)
        model = tree_to_poe(tree, "base", "tool")
        q = model.sample(accuracy_samples, 1)
        exact = chain_fk(text, "base", "tool", q).astype(float)  # rounding: < 1 ulp
        size = model.size()
        ours_err = [pose_errors(model.fk_batch(q), exact)]
        ours_err += [pose_errors(to_table(model, c).fk_batch(q), exact) for c in CONVENTIONS]
        pos, rot = max(p for p, _ in ours_err) / size, max(r for _, r in ours_err)
        theirs = (
            None
            if n > PIN_FK_MAX
            else pose_errors(
                pinocchio_fk(Source("urdf", "chain.urdf", tree.name, tree, data), model, q), exact
            )
        )
        errors.append((n, pos, rot, theirs and theirs[0] / size, theirs and theirs[1]))
        pin_cells = "n/a | n/a" if theirs is None else f"{theirs[0] / size:.2e} | {theirs[1]:.2e}"
        lines.append(
            f"| {n} | {size:.3g} | "
            + " | ".join(f"{p / size:.2e}" for p, _ in ours_err)
            + f" | {rot:.2e} | {pin_cells} |"
        )
    notes = [
        f"Largest chain ({sizes[-1]} joints): peak allocation of the conversion "
        f"{peak_alloc(ours) / 2**20:.1f} MiB.",  # ours: the last chain's
        f"yourdfpy's own load of these chains (not ours; excluded above): {', '.join(loads)}.",
        "",
        f"Worst FK error at {accuracy_samples} configurations against an extended-precision FK "
        "of the URDF text (benchmarks/reference.py): position relative to the robot's size for "
        "the POE model and each convention, and the worst rotation error (rad); Pinocchio's own "
        f"beside them (n/a beyond {PIN_FK_MAX} joints: its Data needs O(n^3) memory).",
        "",
        f"| joints | size | POE | {' | '.join(CONVENTIONS)} | rotation | Pinocchio "
        "| Pinocchio rotation |",
        "|" + "---:|" * (len(CONVENTIONS) + 6),
    ]
    return rows, [*_fits(sizes, times, errors), *notes, *lines]


def _fits(sizes: list[int], times: list[float], errors: list[tuple]) -> list[str]:
    """Linear fit of time against joints, and log-log slopes of time and error."""
    n_arr, t_arr = np.array(sizes, float), np.array(times)
    b, a = np.polyfit(n_arr, t_arr, 1)
    r2 = 1 - np.sum((t_arr - (a + b * n_arr)) ** 2) / np.sum((t_arr - t_arr.mean()) ** 2)
    big = n_arr >= 100 if (n_arr >= 100).sum() >= 2 else n_arr > 0
    slope = np.polyfit(np.log(n_arr[big]), np.log(t_arr[big]), 1)[0]
    out = [
        f"Time against joints: t = {a * 1e3:.3g} ms + {b * 1e6:.3g} us x n (R^2 = {r2:.4f}); "
        f"log-log slope for n >= {int(n_arr[big].min())}: {slope:.2f} (1 = linear); per joint: "
        + ", ".join(f"{n}: {t / n * 1e6:.0f} us" for n, t in zip(sizes, times, strict=True))
    ]
    floor = 2.0**-60  # an error of exactly 0 has no logarithm

    def loglog(k: int, rows: list[tuple]) -> str:
        x = np.log([r[0] for r in rows])
        return f"{np.polyfit(x, np.log([max(r[k], floor) for r in rows]), 1)[0]:.2f}"

    theirs = [e for e in errors if e[3] is not None]
    slopes = (
        "Worst error against joints, log-log slope (<= 1: no faster than linear): ours, "
        f"position / size {loglog(1, errors)}, rotation {loglog(2, errors)}"
    )
    if len(theirs) > 1:
        slopes += f"; Pinocchio (n <= {PIN_FK_MAX}) {loglog(3, theirs)} and {loglog(4, theirs)}"
    return [*out, slopes]


def at_the_bounds(directory: Path, quick: bool) -> list[str]:
    """Whole commands (new processes) on random chains up to the bounds (urdf2dh/tolerances.py):
    convert at 1,000 joints and at the bound, time and peak memory, and how time scales (a
    linear cost gives 10 times the time beyond start-up for 10 times the joints); verify's peak
    memory at 100 and 1,000 joints. Goals: convert at the bound within 15 s and 2 GiB, verify of
    1,000 joints within 1 GiB."""
    lines = []
    sizes = (1000, JOINTS)
    runs = {}
    for n in sizes:
        path = directory / f"chain{n}.urdf"
        path.write_text(random_chain_urdf(n, n - 1)[0])  # n - 1 joints and the fixed tool's
        out = directory / f"chain{n}.txt"
        runs[n] = run_process(["-m", "urdf2dh.cli", "convert", str(path), "-o", str(out)], 2)
    start = run_process(["-m", "urdf2dh.cli", "--help"], 1).seconds
    (small, large), (t_small, t_large) = sizes, (runs[sizes[0]].seconds, runs[sizes[1]].seconds)
    per_joint = (t_large - t_small) / (large - small)
    slope = np.log((t_large - start) / max(t_small - start, 1e-3)) / np.log(large / small)
    met = t_large <= GOAL_SECONDS and runs[large].peak_bytes <= GOAL_BYTES
    lines.append(
        "convert (whole command) of random chains: "
        + "; ".join(
            f"{n:,} joints: {runs[n].seconds:.2f} s, {runs[n].peak_bytes / 2**20:.0f} MiB"
            for n in sizes
        )
        + f"; start-up {start:.2f} s; {per_joint * 1e3:.2f} ms per joint beyond 1,000; log-log "
        f"slope of time beyond start-up {slope:.2f} (1 = linear). Goal at the bound "
        f"({JOINTS:,} joints, refused beyond): <= {GOAL_SECONDS:g} s and <= 2 GiB "
        f"({'met' if met else 'NOT met'})."
    )
    verified = {}
    for n in (100, 1000):
        path = directory / f"verify{n}.urdf"
        path.write_text(random_chain_urdf(n, n - 1)[0])
        samples = "100" if quick else "1000"
        verified[n] = run_process(["-m", "urdf2dh.cli", "verify", str(path), "--samples", samples],
                                  1)  # fmt: skip
    met = verified[1000].peak_bytes <= VERIFY_GOAL_BYTES
    lines.append(
        "verify (whole command): "
        + "; ".join(
            f"{n:,} joints: {verified[n].seconds:.2f} s, {verified[n].peak_bytes / 2**20:.0f} MiB"
            for n in verified
        )
        + f" (Pinocchio's Data alone would take ~8 GB at 500 joints). Goal: <= 1 GiB at 1,000 "
        f"joints ({'met' if met else 'NOT met'})."
    )
    return lines
