"""The shipped JSON Schemas (urdf2dh/schemas/, draft 2020-12) describe what urdf2dh writes: every
table file, POE model file and calibration report written for bundled robots in every convention
and format validates against the schema its ``schema`` field names; the schemas name the same
parameters as the conventions' registry; the readers take the schema's name and the older one."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from jsonschema import Draft202012Validator
from referencing import Registry, Resource

import urdf2dh
from urdf2dh import schemas
from urdf2dh.cli import main
from urdf2dh.conventions import NAMES, get
from urdf2dh.emit.formats import render

ROOT = Path(__file__).resolve().parents[1]
REGISTRY = Registry().with_resources(
    (name, Resource.from_contents(schemas.load(name))) for name in schemas.names()
)
ROBOTS = ("ur5", "panda", "stanford", "scara", "so100", "puma560-actual", "kinova", "tiago-arm")


def validate(tree: dict) -> None:
    """Validate ``tree`` against the schema its ``schema`` field names (a POE file's is
    optional: ``format: poe`` names it too)."""
    name = tree.get("schema", schemas.POE_FILE if tree.get("format") == "poe" else None)
    if name == "urdf2dh/1":
        name = schemas.TABLE_FILE
    validator = Draft202012Validator(schemas.load(name), registry=REGISTRY)
    errors = sorted(validator.iter_errors(tree), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{list(e.path)}: {e.message}" for e in errors[:5])


def test_the_schemas_are_valid_draft_2020_12_named_by_their_id():
    for name in schemas.names():
        schema = schemas.load(name)
        Draft202012Validator.check_schema(schema)
        assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
        assert schema["$id"] == name
    with pytest.raises(ValueError, match="no schema named 'urdf2dh/2'"):
        schemas.load("urdf2dh/2")


def test_the_table_schema_names_each_conventions_parameters():
    """Each place (base, rows, tool) of each convention takes exactly the parameter records the
    convention's registry lists, and no other."""
    schema = schemas.load(schemas.TABLE_FILE)
    defs = schema["$defs"]

    def records(ref: dict) -> set[frozenset[str]]:
        refs = [ref] if "$ref" in ref else ref["oneOf"]
        return {frozenset(defs[r["$ref"].split("/")[-1]].get("properties", {})) for r in refs}

    by_convention = {
        rule["if"]["properties"]["convention"]["const"]: rule["then"]["properties"]
        for rule in schema["allOf"]
    }
    assert set(by_convention) == set(NAMES)
    for name, places in by_convention.items():
        conv = get(name)
        expected = {
            "base": conv.base_types,
            "joints": conv.row_types,
            "tool": conv.tool_types,
        }
        for place, types in expected.items():
            entry = places[place]["items"] if place == "joints" else places[place]
            rule = entry["properties"]["params"]
            assert records(rule) == {frozenset(t.quantities()) for t in types}, (name, place)


@pytest.mark.parametrize("robot", ROBOTS)
def test_every_written_table_and_poe_file_validates(robot):
    model = urdf2dh.load(robot)
    for convention in NAMES:
        table = urdf2dh.to_table(model, convention)
        for text in (render(table, "json"), render(table, "yaml")):
            tree = yaml.safe_load(text)
            assert tree["schema"] == schemas.TABLE_FILE
            validate(tree)
    poe = yaml.safe_load(render(urdf2dh.to_table(model, "dh"), "poe"))
    assert poe["schema"] == schemas.POE_FILE
    validate(poe)


def test_the_bundled_poe_files_validate():
    """Hand-written POE files (no ``schema`` field) are valid too."""
    for robot in ("puma560-nominal", "puma560-actual"):
        validate(yaml.safe_load((ROOT / "robots" / f"{robot}.yaml").read_text()))


def test_a_table_with_mimic_rows_validates(tmp_path):
    out = tmp_path / "tables.json"
    source = str(ROOT / "tests" / "data" / "parallelogram.urdf")
    assert main(["convert", source, "--format", "json", "-o", str(out)]) == 0
    validate(json.loads(out.read_text()))


def test_a_calibration_report_validates(tmp_path):
    poses, report = tmp_path / "poses.csv", tmp_path / "report.json"
    argv = ["measure", "ur5", "--configs", "40", "--noise-pos", "1e-5", "--noise-rot", "1e-5"]
    assert main([*argv, "--seed", "3", "-o", str(poses)]) == 0
    out = tmp_path / "identified.json"
    argv = ["calibrate", "ur5", str(poses), "--holdout", "0.25", "--format", "json"]
    assert main([*argv, "-o", str(out), "--report", str(report)]) == 0
    tree = json.loads(report.read_text())
    assert tree["schema"] == schemas.CALIBRATION_REPORT
    validate(tree)
    validate(tree["model"])
    validate(json.loads(out.read_text()))


def test_a_report_missing_a_field_or_a_table_with_a_wrong_record_is_invalid():
    """The schemas can fail: a table whose dh row holds Craig's order is still four numbers, but
    a row of a cpc table without ``b`` is not."""
    tree = urdf2dh.to_table(urdf2dh.load("ur5"), "cpc").to_dict()
    del tree["joints"][2]["params"]["b"]
    with pytest.raises(AssertionError, match=r"\['joints', 2, 'params'\]"):
        validate(tree)
    tree = urdf2dh.to_table(urdf2dh.load("ur5"), "dh").to_dict()
    tree["tool"]["params"]["alpha"] = 0.0
    with pytest.raises(AssertionError, match=r"\['tool', 'params'\]"):
        validate(tree)


def test_the_readers_take_the_schema_name_and_the_older_one(tmp_path, capsys):
    table = urdf2dh.to_table(urdf2dh.load("ur5"), "mdh").to_dict()
    for name in schemas.TABLE_FILE_NAMES:
        path = tmp_path / "table.json"
        path.write_text(json.dumps(table | {"schema": name}))
        assert main(["convert", str(path), "--convention", "dh"]) == 0
    poe = yaml.safe_load(render(urdf2dh.to_table(urdf2dh.load("ur5"), "dh"), "poe"))
    path = tmp_path / "model.yaml"
    for tree in (poe, {k: v for k, v in poe.items() if k != "schema"}):
        path.write_text(yaml.safe_dump(tree))
        assert main(["info", str(path)]) == 0
    path.write_text(yaml.safe_dump(poe | {"schema": "urdf2dh/poe/9"}))
    capsys.readouterr()
    assert main(["info", str(path)]) == 2
    assert f"schema must be {schemas.POE_FILE} (or absent)" in capsys.readouterr().err


def test_the_schemas_bound_the_joints_as_the_readers_do():
    from urdf2dh.tolerances import JOINTS

    for name in (schemas.TABLE_FILE, schemas.POE_FILE):
        assert schemas.load(name)["properties"]["joints"]["maxItems"] == JOINTS
