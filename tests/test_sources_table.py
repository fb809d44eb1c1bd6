"""The table of SOURCE readers: which reader claims which file, the XML root sniffed from the text,
and a reader added to the table reads its files (the extension point in use)."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from urdf2dh.io import sources
from urdf2dh.io.encodings import xml_root
from urdf2dh.io.sources import READERS, Content, Reader, Source, open_source


def claimant(name: str, text: str | bytes) -> str | None:
    data = text.encode() if isinstance(text, str) else text
    content = Content(Path(name), name, data, None)
    return next((r.name for r in READERS.values() if r.claims(content)), None)


@pytest.mark.parametrize(
    ("name", "text", "reader"),
    [
        ("arm.urdf.xacro", "<robot xmlns:xacro='x'/>", "xacro"),
        ("arm.urdf", "<robot name='r'/>", "urdf"),
        ("arm.xml", "<robot name='r'/>", "urdf"),
        ("arm", "  <?xml version='1.0'?>\n<robot name='r'/>", "urdf"),
        ("arm.yaml", "format: poe\njoints: []\n", "poe"),
        ("arm.json", '{"schema": "x", "rows": []}', "table"),
        ("arm.yaml", "a: 1\n", None),
        ("arm.yaml", "just words", None),
    ],
)
def test_the_first_reader_that_claims_a_file_reads_it(name, text, reader):
    assert claimant(name, text) == reader


def test_every_reader_module_reads_sources():
    for reader in READERS.values():
        module = importlib.import_module(f"urdf2dh.io.{reader.module}")
        assert callable(module.read_source), reader.name


@pytest.mark.parametrize(
    ("data", "root"),
    [
        (b"<robot name='x'/>", "robot"),
        (
            b"\xef\xbb\xbf <?xml version='1.0'?>\n<!-- c -->\n<?pi x?>\n<mujoco model='m'/>",
            "mujoco",
        ),
        (b"<!DOCTYPE robot [<!ENTITY a 'b>'>]>\n<robot/>", "robot"),
        ("<?xml version='1.0' encoding='utf-16'?><mujoco/>".encode("utf-16"), "mujoco"),
        (b"<ns:mujoco xmlns:ns='u'/>", "mujoco"),
        (b"<!-- never closed <robot/>", None),
        (b"format: poe", None),
        (b"<", None),
        (b"", None),
    ],
)
def test_the_root_element_is_sniffed_from_the_text(data, root):
    assert xml_root(data) == root


def test_a_reader_added_to_the_table_reads_its_files(tmp_path, monkeypatch):
    # a format of its own: a text file of one line "chain: <bundled robot>", read as that robot
    def read_source(content, reading):
        robot = content.data.decode().split(":", 1)[1].strip()
        poe = open_source(robot).model()
        return Source("poe", content.display, robot, poe=poe)

    module = type(importlib)("urdf2dh.io.chainfile")
    module.read_source = read_source
    monkeypatch.setitem(importlib.sys.modules, "urdf2dh.io.chainfile", module)
    entry = Reader("chain", "chain", "chain file", "chainfile", lambda c: c.suffix == ".chain")
    monkeypatch.setitem(sources.READERS, "chain", entry)
    path = tmp_path / "arm.chain"
    path.write_text("chain: puma560-nominal\n")
    model = sources.load(str(path))
    assert model.n == 6 and model.name == "puma560-nominal"
    assert "chain" in sources.source_kinds()
