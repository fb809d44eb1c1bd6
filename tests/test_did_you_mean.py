"""A misspelled command, option, choice, robot or link name is answered with the closest valid
names ("did you mean ...?"); a word close to none gets no guess."""

from __future__ import annotations

import pytest

import urdf2dh
from urdf2dh.cli import main
from urdf2dh.errors import UsageError, near


@pytest.mark.parametrize(
    "argv, said",
    [
        (["conver", "ur5"], "invalid choice: 'conver' (did you mean 'convert'?)"),
        (["calibate", "ur5"], "(did you mean 'calibrate'?)"),
        (["convert", "ur5", "--conventoin", "mdh"], "unrecognized arguments: --conventoin mdh "
         "(did you mean --convention?)"),
        (["verify", "ur5", "--sampels=10"], "(did you mean --samples?)"),
        (["convert", "ur5", "--convention", "mhd"], "invalid choice: 'mhd' (did you mean 'mdh'?)"),
        (["export", "ur5", "--to", "linuxnc"], "(did you mean 'linuxcnc'?)"),
        (["convert", "ur55"], "'ur55' is neither a file nor a bundled robot (did you mean 'ur5'?)"),
        (["info", "pnda"], "(did you mean 'panda'?)"),
        (["convert", "ur5", "--tip", "tool00"], "unknown tip link 'tool00' (did you mean "
         "'tool0'?)"),
        (["convert", "panda", "--base", "panda_lnk0"], "unknown base link 'panda_lnk0' (did you "
         "mean 'panda_link0'?)"),
        (["convert", "panda", "--all-tips", "--base", "Panda_Link0"], "(did you mean "
         "'panda_link0'?)"),
    ],
)  # fmt: skip
def test_a_misspelled_name_gets_the_closest(argv, said, capsys):
    try:
        code = main(argv)
    except SystemExit as e:  # argparse's errors
        code = e.code
    assert code == 2
    err = capsys.readouterr().err
    assert said in err.splitlines()[-1], err  # on the error's one line


def test_nothing_close_gets_no_guess(capsys):
    assert main(["convert", "qqqqqqq"]) == 2
    assert "did you mean" not in capsys.readouterr().err
    assert near("zzz", ["dh", "mdh"]) == ""


def test_the_python_api_says_it_too():
    model = urdf2dh.load("ur5")
    with pytest.raises(UsageError, match=r"unknown convention 'hayatti' \(did you mean 'hayati'"):
        urdf2dh.to_table(model, "hayatti")
    with pytest.raises(UsageError, match=r"\(did you mean 'json'\?\)"):
        urdf2dh.render(urdf2dh.to_table(model), "jsno")
    with pytest.raises(UsageError, match=r"\(did you mean 'kdl'\?\)"):
        urdf2dh.export(model, "kdll")
    with pytest.raises(urdf2dh.errors.ChainError, match=r"did you mean 'wrist_3_link'\?"):
        urdf2dh.load("ur5", tip="wrist3_link")
