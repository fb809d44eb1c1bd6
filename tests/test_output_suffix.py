"""The output is what its file name says: without --format, the suffix of -o chooses the format
of every command that writes a table or model (convert, calibrate, diff), and a suffix that
--format contradicts (or one the command does not write) is refused before anything is read,
with nothing written."""

from __future__ import annotations

import json

import pytest
import yaml
from lxml import etree

from urdf2dh.cli import main
from urdf2dh.emit.formats import SUFFIXES, format_of


def written(path, capsys):
    text = path.read_text()
    capsys.readouterr()
    return text


def looks_like(fmt: str, text: str) -> bool:
    """Whether ``text`` is a file of format ``fmt`` (parsed where it has a parser)."""
    if fmt == "json":
        return json.loads(text)["convention"] == "dh"
    if fmt == "yaml":
        return yaml.safe_load(text)["convention"] == "dh"
    if fmt == "poe":
        return yaml.safe_load(text)["format"] == "poe"
    if fmt == "urdf":
        return etree.fromstring(text.encode()).tag == "robot"
    if fmt == "csv":
        return text.startswith("row,joint,type,")
    if fmt == "markdown":
        return "| joint |" in text or "|---" in text or "| --- |" in text
    return text.startswith("ur5 (") and "standard D-H" in text  # text


@pytest.mark.parametrize(
    "suffix", [s for suffixes in SUFFIXES.values() for s in suffixes] + [".JSON", ".Yml"]
)
def test_the_suffix_of_o_chooses_the_format(suffix, tmp_path, capsys):
    fmt = format_of("x" + suffix)
    assert fmt is not None
    out = tmp_path / f"ur5{suffix}"
    assert main(["convert", "ur5", "-o", str(out)]) == 0
    assert looks_like(fmt, written(out, capsys)), (suffix, out.read_text()[:200])
    if fmt in ("json", "yaml", "poe", "urdf"):  # what it wrote reads back as a SOURCE
        assert main(["convert", str(out), "--format", "json"]) == 0
        assert json.loads(capsys.readouterr().out)["convention"] == "dh"


def test_an_unknown_suffix_is_the_default_format(tmp_path, capsys):
    out = tmp_path / "ur5.table"
    assert main(["convert", "ur5", "-o", str(out)]) == 0
    assert looks_like("text", written(out, capsys))
    assert main(["convert", "ur5", "--format", "csv", "-o", str(out)]) == 0
    assert looks_like("csv", written(out, capsys))


@pytest.mark.parametrize(
    "argv, said",
    [
        (["convert", "no-such-robot", "--format", "yaml", "-o", "OUT.json"], "names a json file"),
        (["convert", "no-such-robot", "--format", "yaml", "-o", "OUT.poe.yaml"], "names a poe"),
        (["convert", "no-such-robot", "--format", "text", "-o", "OUT.csv"], "names a csv file"),
        (["diff", "no-such", "robot", "-o", "OUT.yaml"], "which diff does not write"),
        (["diff", "no-such", "robot", "--format", "text", "-o", "OUT.json"], "names a json"),
        (
            ["calibrate", "no-such", "m.csv", "--format", "json", "-o", "OUT.yaml"],
            "names a yaml file",
        ),
    ],
)
def test_a_contradicting_suffix_is_refused_before_anything_is_read(argv, said, tmp_path, capsys):
    argv = [a.replace("OUT", str(tmp_path / "out")) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert said in err and "no-such" not in err, err  # the source was never looked at
    assert list(tmp_path.iterdir()) == []


def test_diff_writes_json_to_a_json_file(tmp_path, capsys):
    out = tmp_path / "d.json"
    assert main(["diff", "puma560-nominal", "puma560-actual", "-o", str(out)]) == 0
    assert json.loads(written(out, capsys))["convention"] == "dh"


def test_calibrate_writes_the_table_file_its_name_says(tmp_path, capsys):
    """The README's `calibrate ... -o ur10-id.yaml`, on a small synthetic set: the file is a
    YAML table file, which `convert` reads back."""
    m = tmp_path / "m.csv"
    assert main(["measure", "puma560-actual", "--configs", "40", "--seed", "3", "-o", str(m)]) == 0
    out = tmp_path / "id.yaml"
    # the actual PUMA's joints are helical: the offsets alone leave a tenth of its size (refused)
    argv = ["calibrate", "puma560-nominal", str(m), "--identify", "full", "--helical", "all",
            "-o", str(out)]  # fmt: skip
    assert main(argv) == 0
    tree = yaml.safe_load(written(out, capsys))
    assert tree["schema"].startswith("urdf2dh/schemas/table-file")
    assert main(["convert", str(out), "--convention", tree["convention"]]) == 0
    poe = tmp_path / "id.poe.yaml"
    argv = ["calibrate", "puma560-nominal", str(m), "--identify", "full", "--helical", "all",
            "-o", str(poe)]  # fmt: skip
    assert main([*argv, "--convention", "poe", "--format", "yaml"]) == 0
    assert yaml.safe_load(written(poe, capsys))["format"] == "poe"


def test_a_poe_model_file_may_be_named_yaml(tmp_path, capsys):
    """A POE model file is a YAML document: `--format poe -o x.yaml` writes it; `--format yaml -o
    x.poe.yaml` (a table file named as a POE model file) is refused."""
    out = tmp_path / "panda.yaml"
    assert main(["convert", "panda", "--format", "poe", "-o", str(out)]) == 0
    assert yaml.safe_load(written(out, capsys))["format"] == "poe"
    assert main(["convert", "panda", "--format", "yaml", "-o", str(tmp_path / "p.poe.yaml")]) == 2
    assert "names a poe file" in capsys.readouterr().err
