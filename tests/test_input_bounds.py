"""Every input is bounded (urdf2dh/tolerances.py, docs/limits.md): sources that are not regular
files are refused before a byte is read, files and chains beyond the bounds are refused in one line
naming the bound, libxml2's own limits are said as what they are, and a name of megabytes is
shortened in every message."""

from __future__ import annotations

import json
import os
import re
import threading
from pathlib import Path

import pytest
from chains import random_chain_urdf

import urdf2dh
from urdf2dh import tolerances
from urdf2dh.cli import main
from urdf2dh.errors import MESSAGE_LENGTH, SHOWN_LENGTH, InputError, one_line, shown
from urdf2dh.io.files import read_file
from urdf2dh.tolerances import FILE_BYTES, JOINTS, MEASUREMENT_BYTES


def one_line_error(capsys, argv: list[str]) -> str:
    """Run the command, which must refuse its input (exit 2), and return its one error line."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("urdf2dh: error: "), err[:500]
    return lines[0]


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path, capsys):
    fifo = tmp_path / "robot.urdf"
    os.mkfifo(fifo)
    outcome: list[str] = []
    worker = threading.Thread(
        target=lambda: outcome.append(one_line_error(capsys, ["convert", str(fifo)])),
        daemon=True,
    )
    worker.start()
    worker.join(timeout=30)
    assert not worker.is_alive(), "convert blocked on a FIFO with no writer"
    assert outcome == [f"urdf2dh: error: {fifo}: not a regular file (a device, FIFO or socket); "
                       "urdf2dh reads files"]  # fmt: skip


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/null"])
def test_a_device_is_refused(capsys, device):
    line = one_line_error(capsys, ["convert", device])
    assert line.endswith(f"{device}: not a regular file (a device, FIFO or socket); urdf2dh "
                         "reads files")  # fmt: skip


def test_a_directory_is_refused(tmp_path, capsys):
    (tmp_path / "robot.urdf").mkdir()
    line = one_line_error(capsys, ["info", str(tmp_path / "robot.urdf")])
    assert line.endswith("robot.urdf: is a directory, not a file")


def test_a_regular_file_beyond_the_bound_is_refused(tmp_path, capsys):
    path = tmp_path / "huge.urdf"
    with open(path, "wb") as f:
        f.write(b"<robot name='r'>")
        f.truncate(FILE_BYTES + 1)  # sparse: no time to write
    out = tmp_path / "out.json"
    line = one_line_error(capsys, ["convert", str(path), "-o", str(out)])
    assert line == f"urdf2dh: error: {path}: larger than 16 MiB, the most urdf2dh reads"
    assert not out.exists()


def test_a_measurement_file_has_a_bound_of_its_own(tmp_path, capsys):
    """Measurement files are bounded for a million poses (MEASUREMENT_BYTES), not by the 16 MiB
    of a robot file: a file beyond FILE_BYTES is read (here one row, its last cell padded with
    spaces, so that it then fails for a reason of its own), one beyond MEASUREMENT_BYTES refused
    in one line."""
    joints = [j.name for j in urdf2dh.load("ur5").joints]
    head = ",".join([*joints, "x", "y", "z"]) + "\n0,0,0,0,0,0,0.1,0.2,0.3"
    path = tmp_path / "poses.csv"
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(b" " * (FILE_BYTES + 1) + b"\n")
    line = one_line_error(capsys, ["calibrate", "ur5", str(path)])
    assert line.startswith(f"urdf2dh: error: {path}, line 2: not a CSV row (field larger than")
    with open(path, "wb") as f:
        f.write(head.encode())
        f.truncate(MEASUREMENT_BYTES + 1)  # sparse: no time to write
    out = tmp_path / "out.json"
    line = one_line_error(capsys, ["calibrate", "ur5", str(path), "-o", str(out)])
    assert line == f"urdf2dh: error: {path}: larger than 512 MiB, the most urdf2dh reads"
    assert not out.exists()


def test_read_file_reads_up_to_its_limit_exactly(tmp_path):
    path = tmp_path / "ten"
    path.write_bytes(b"0123456789")
    assert read_file(path, "ten", limit=10) == b"0123456789"
    with pytest.raises(InputError, match=r"^ten: larger than 9 bytes, the most urdf2dh reads$"):
        read_file(path, "ten", limit=9)


def test_a_urdf_beyond_the_joint_bound_is_refused_before_it_is_read_joint_by_joint(
    tmp_path, capsys
):
    path = tmp_path / "long.urdf"
    path.write_text(random_chain_urdf(1, JOINTS - 1)[0])  # and its tool's fixed joint
    assert main(["info", str(path)]) == 0  # JOINTS joints: read
    capsys.readouterr()
    path.write_text(random_chain_urdf(1, JOINTS)[0])  # JOINTS + 2 links, JOINTS + 1 joints
    line = one_line_error(capsys, ["convert", str(path)])
    assert line == (
        f"urdf2dh: error: {path}: {JOINTS + 1:,} joints; urdf2dh reads URDFs of at most "
        f"{JOINTS:,} joints ({JOINTS + 1:,} links)"
    )


def test_a_poe_file_beyond_the_joint_bound_is_refused(tmp_path, capsys):
    twist = [0, 0, 1, 0, 0, 0]
    tree = {"format": "poe", "joints": [{"name": f"j{k}", "twist": twist}
                                        for k in range(JOINTS + 1)],
            "tool": {"twist": [0, 0, 0, 1, 0, 0]}}  # fmt: skip
    path = tmp_path / "long.json"
    path.write_text(json.dumps(tree))
    line = one_line_error(capsys, ["convert", str(path)])
    assert line.endswith(f"long.json: {JOINTS + 1:,} joints; urdf2dh reads chains of at most "
                         f"{JOINTS:,}")  # fmt: skip


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ('<robot name="' + "a" * 11_000_000 + '"/>', "Buffer size limit exceeded"),
        ('<robot name="r"><link name="l">' + "x" * 11_000_000 + "</link></robot>",
         "Text node too long"),
        ('<robot name="r">' + "<a>" * 300 + "</a>" * 300 + "</robot>",
         "Excessive depth in document: 256"),
    ],
)  # fmt: skip
def test_libxml2_limits_are_not_called_malformed_xml(tmp_path, capsys, text, reason):
    path = tmp_path / "big.urdf"
    path.write_text(text)
    line = one_line_error(capsys, ["convert", str(path)])
    assert f"{path}: beyond the XML parser's limits (" in line and reason in line
    assert "malformed" not in line and "XML_PARSE_HUGE" not in line


@pytest.mark.parametrize("character", ["x", "\n", "\u00e9"])
def test_a_name_of_megabytes_is_shortened_in_the_message(tmp_path, capsys, character):
    name = character * 1_000_000  # 5 MB of "&#10;" in the file, under libxml2's 10 MB
    path = tmp_path / "named.urdf"
    path.write_text(
        '<robot name="r"><link name="base"/><joint name="j" type="revolute">'
        f'<parent link="base"/><child link="{name}"/></joint></robot>'.replace("\n", "&#10;")
    )
    line = one_line_error(capsys, ["convert", str(path)])
    assert line == (
        f"urdf2dh: error: {path}: joint 'j' names undeclared link {shown(name)} as its child"
    )
    assert "(1000000 characters)" in line and len(line) < 2 * SHOWN_LENGTH + len(str(path)) + 100


def test_the_command_line_cuts_any_error_line_beyond_its_bound():
    long = "a: " + "x" * 50_000 + " :end"
    line = one_line(long)
    assert len(line) <= MESSAGE_LENGTH + 40
    assert line.startswith("a: xxx") and line.endswith("xxx :end")
    assert "(50,008 characters)" in line
    assert one_line("short\nmessage") == "short\\nmessage"


def test_the_limits_page_example_runs():
    """docs/limits.md's Python example (the bounds, and a FIFO refused)."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "limits.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    for block in blocks:
        exec(compile(block, "docs/limits.md", "exec"), {})


def test_the_limits_page_names_every_bound():
    text = (Path(__file__).resolve().parents[1] / "docs" / "limits.md").read_text()
    for name in tolerances.BOUNDS:
        assert f"`{name}`" in text, name
    assert "16 MiB" in text and f"{tolerances.JOINTS:,}" in text
    assert f"{tolerances.VERIFY_JOINTS:,}" in text


def comb_urdf(n: int) -> str:
    """A chain of ``n`` joints with a fixed leaf on every link: ``n`` chains of 2 to ``n + 1``
    joints (the leaf's fixed one counted), n (n + 3) / 2 in all."""
    links, joints = ['<link name="c0"/>'], []
    for i in range(1, n + 1):
        links += [f'<link name="c{i}"/>', f'<link name="t{i}"/>']
        joints += [
            f'<joint name="j{i}" type="revolute"><parent link="c{i - 1}"/><child link="c{i}"/>'
            '<origin xyz="0.1 0 0" rpy="0.3 0 0"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>',
            f'<joint name="f{i}" type="fixed"><parent link="c{i}"/><child link="t{i}"/></joint>',
        ]
    return '<robot name="comb">' + "".join(links + joints) + "</robot>"


def test_all_tips_is_bounded_by_the_joints_of_every_chain(tmp_path, capsys):
    """A comb of 150 links has 11,475 joints on its 150 chains: refused (a comb of 3,000
    would take an hour); one of 100 links (5,150) is converted."""
    path = tmp_path / "comb.urdf"
    path.write_text(comb_urdf(150))
    out = tmp_path / "out"
    line = one_line_error(capsys, ["convert", str(path), "--all-tips", "-o", f"{out}/"])
    assert line == (
        f"urdf2dh: error: {path}: the 150 chains have 11,475 joints in all; one run converts "
        f"at most {JOINTS:,} (name fewer tips with --tip)"
    )
    assert not out.exists()
    path.write_text(comb_urdf(100))
    assert main(["convert", str(path), "--all-tips", "-o", f"{out}/"]) == 0
    assert len(os.listdir(out)) == 100
