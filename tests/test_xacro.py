"""xacro sources: expanded with the xacro package, ROS packages found via --package-path."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

import urdf2dh
from urdf2dh import load
from urdf2dh.cli import main
from urdf2dh.errors import InputError, Remedy
from urdf2dh.io.sources import open_source
from urdf2dh.io.xacro import XacroOptions

DATA = Path(__file__).parent / "data" / "xacro"
XACRO = str(DATA / "demo_arm.urdf.xacro")
PACKAGES = {"demo_description": str(DATA / "demo_description")}


def test_xacro_gives_the_same_chain_as_its_expansion():
    model = open_source(XACRO, package_paths=PACKAGES).model()
    plain = load(str(DATA / "demo_arm.urdf"))
    assert [j.name for j in model.joints] == [j.name for j in plain.joints]
    q = np.random.default_rng(8).uniform(-2.5, 2.5, (50, model.n))
    np.testing.assert_allclose(model.fk_batch(q), plain.fk_batch(q), atol=1e-15)
    assert (model.base_link, model.tip_link) == ("base_link", "tool0")


def test_xacro_source_verifies_against_pinocchio():
    report = urdf2dh.verify(XACRO, samples=100, xacro=XacroOptions(packages=PACKAGES))
    assert report.ok, [(c.label, c.position, c.rotation) for c in report.checks]


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
    text = (
        (DATA / "demo_arm.urdf.xacro")
        .read_text()
        .replace("$(find demo_description)/urdf", "package://demo_description/urdf")
    )
    assert "$(find" not in text.split("-->", 1)[1]
    path = tmp_path / "arm.xacro"
    path.write_text(text)
    with pytest.raises(InputError, match="needs ROS package 'demo_description'") as e:
        open_source(str(path))
    assert "--" not in str(e.value)  # the library says what is wrong; the CLI names the option
    assert e.value.remedy == Remedy("xacro.packages", "; point at its directory with {}",
                                    "demo_description=DIR")  # fmt: skip
    assert open_source(str(path), package_paths=PACKAGES).model().n == 4


def test_cli_package_path_option(capsys):
    code = main(
        [
            "convert",
            XACRO,
            "--package-path",
            f"demo_description={PACKAGES['demo_description']}",
            "--format",
            "csv",
        ]
    )
    assert code == 0
    assert "wrist_joint" in capsys.readouterr().out
    code = main(["convert", XACRO, "--package-path", "demo_description=/no/such/dir"])
    assert code == 2 and "/no/such/dir: no such directory" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["convert", XACRO, "--package-path", "demo_description"])
    assert "expected NAME=DIR" in capsys.readouterr().err


def test_broken_xacro_is_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.urdf.xacro"
    bad.write_text(
        '<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<link name="${undefined_property}"/></robot>'
    )
    assert main(["convert", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "xacro cannot expand it" in err and "undefined" in err


def test_without_the_xacro_package_an_install_hint(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "xacro", None)  # as if not installed
    assert main(["convert", XACRO]) == 2
    assert "pip install xacro" in capsys.readouterr().err


ARM_PACKAGE = DATA / "arm_description"
ARM = str(ARM_PACKAGE / "urdf" / "arm.urdf.xacro")
ARM_OPTIONS = ["--package-path", f"arm_description={ARM_PACKAGE}"]


@pytest.mark.parametrize("arm_type", ["small", "large"])
def test_xacro_arguments_choose_the_robot_as_urs_description_does(arm_type, capsys):
    """UR's ROS 2 description needs name:= and ur_type:=; this fixture has its structure: the
    name used before its default, the dimensions a YAML file chosen by argument."""
    import yaml

    args = ["--xacro-arg", "name:=my_arm", "--xacro-arg", f"arm_type:={arm_type}"]
    assert main(["convert", ARM, *ARM_OPTIONS, *args, "--format", "json"]) == 0
    table = json.loads(capsys.readouterr().out)
    assert table["robot"] == "my_arm"
    dims = yaml.safe_load((ARM_PACKAGE / "config" / arm_type / "dims.yaml").read_text())
    lengths = sorted(abs(j["params"][k]) for j in table["joints"] for k in ("d", "a"))
    expected = sorted([abs(v) for v in dims.values()] + [0.0] * 6)
    assert lengths == pytest.approx(expected, abs=1e-12)
    assert main(["verify", ARM, *ARM_OPTIONS, *args, "--samples", "50"]) == 0


def test_an_argument_may_name_the_yaml_file_itself(capsys):
    dims = ARM_PACKAGE / "config" / "small" / "dims.yaml"
    assert (
        main(
            [
                "convert",
                ARM,
                *ARM_OPTIONS,
                "--xacro-arg",
                "name:=a",
                "--xacro-arg",
                f"dims_file:={dims}",
                "--format",
                "csv",
            ]
        )
        == 0
    )
    assert "0.24365" in capsys.readouterr().out


def test_a_missing_argument_is_named_with_the_option(capsys):
    assert main(["convert", ARM, *ARM_OPTIONS]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--xacro-arg name:=VALUE" in err
    assert main(["convert", ARM, *ARM_OPTIONS, "--xacro-arg", "name:=a"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "config/unset/dims.yaml" in err
    with pytest.raises(SystemExit):
        main(["convert", ARM, "--xacro-arg", "name=a"])
    assert "expected NAME:=VALUE" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("expression", "options", "message"),
    [
        (
            "${9**9**9}",
            ["--xacro-timeout", "2"],
            "took longer than 2 s (--xacro-timeout SECONDS allows more)",
        ),
        ("${len('x'*10**10)}", [], "needs more than 1024 MiB of memory (--xacro-memory MIB allows"),
        ("${len('x'*10**8)}", ["--xacro-memory", "64"], "needs more than 64 MiB"),
    ],
)
def test_expansion_is_bounded_in_time_and_memory(tmp_path, capsys, expression, options, message):
    bomb = tmp_path / "bomb.urdf.xacro"
    bomb.write_text(
        '<robot name="b" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        f'<link name="l{expression}"/></robot>'
    )
    out = tmp_path / "out.json"
    assert main(["convert", str(bomb), *options, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert list(tmp_path.iterdir()) == [bomb]


def test_a_bound_that_is_not_hit_changes_nothing(capsys):
    package = f"demo_description={PACKAGES['demo_description']}"
    assert (
        main(
            [
                "convert",
                XACRO,
                "--package-path",
                package,
                "--xacro-timeout",
                "60",
                "--xacro-memory",
                "2048",
                "--format",
                "csv",
            ]
        )
        == 0
    )
    assert "wrist_joint" in capsys.readouterr().out


def test_xacro_is_a_dependency_and_the_old_extra_still_installs():
    """`pip install urdf2dh` reads xacro descriptions; `urdf2dh[xacro]` (old install lines)
    still names an extra that exists, now empty."""
    tomllib = pytest.importorskip("tomllib")
    root = Path(__file__).resolve().parents[1]
    project = tomllib.loads((root / "pyproject.toml").read_text())["project"]
    assert [d for d in project["dependencies"] if d.startswith("xacro")] == ["xacro>=2.0"]
    assert project["optional-dependencies"]["xacro"] == []
