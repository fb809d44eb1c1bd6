"""xacro sources: expanded with the xacro package, ROS packages found via --package-path."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from urdf2dh.cli import main
from urdf2dh.errors import InputError
from urdf2dh.sources import open_source
from urdf2dh.verify import verify

DATA = Path(__file__).parent / "data" / "xacro"
XACRO = str(DATA / "demo_arm.urdf.xacro")
PACKAGES = {"demo_description": str(DATA / "demo_description")}


def test_xacro_gives_the_same_chain_as_its_expansion():
    model = open_source(XACRO, package_paths=PACKAGES).model()
    plain = open_source(str(DATA / "demo_arm.urdf")).model()
    assert [j.name for j in model.joints] == [j.name for j in plain.joints]
    q = np.random.default_rng(8).uniform(-2.5, 2.5, (50, model.n))
    np.testing.assert_allclose(model.fk_batch(q), plain.fk_batch(q), atol=1e-15)
    assert (model.base_link, model.tip_link) == ("base_link", "tool0")


def test_xacro_source_verifies_against_pinocchio():
    source = open_source(XACRO, package_paths=PACKAGES)
    results = verify(source, source.model(), samples=100)
    assert all(r.ok for r in results), [(r.label, r.position, r.rotation) for r in results]


def test_missing_package_names_it_and_the_option(capsys, tmp_path):
    out = tmp_path / "t.json"
    assert main(["convert", XACRO, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "ROS package 'demo_description'" in err
    assert "--package-path demo_description=DIR" in err
    assert not out.exists()


def test_package_url_is_resolved_too(tmp_path):
    # only package:// is used here (the include goes through $(find) in demo_arm)
    text = (DATA / "demo_arm.urdf.xacro").read_text().replace(
        "$(find demo_description)/urdf", "package://demo_description/urdf")
    assert "$(find" not in text.split("-->", 1)[1]
    path = tmp_path / "arm.xacro"
    path.write_text(text)
    with pytest.raises(InputError, match="--package-path demo_description=DIR"):
        open_source(str(path))
    assert open_source(str(path), package_paths=PACKAGES).model().n == 4


def test_cli_package_path_option(capsys):
    code = main(["convert", XACRO, "--package-path",
                 f"demo_description={PACKAGES['demo_description']}", "--format", "csv"])
    assert code == 0
    assert "wrist_joint" in capsys.readouterr().out
    code = main(["convert", XACRO, "--package-path", "demo_description=/no/such/dir"])
    assert code == 2 and "/no/such/dir: no such directory" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["convert", XACRO, "--package-path", "demo_description"])
    assert "expected NAME=DIR" in capsys.readouterr().err


def test_broken_xacro_is_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.urdf.xacro"
    bad.write_text('<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                   '<link name="${undefined_property}"/></robot>')
    assert main(["convert", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "xacro cannot expand it" in err and "undefined" in err


def test_without_the_xacro_package_an_install_hint(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "xacro", None)  # as if not installed
    assert main(["convert", XACRO]) == 2
    assert "pip install xacro" in capsys.readouterr().err
