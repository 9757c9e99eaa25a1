"""The README's printed friction table is what `contactvib friction --pa 0.65 --fe 360` prints."""

import re
from pathlib import Path

from contactvib.cli import main

README = (Path(__file__).resolve().parents[2] / "README.md").read_text()


def test_friction_table_is_the_commands_output(capsys):
    i = README.index("`contactvib friction --pa 0.65 --fe 360` (")
    expected = re.search(r"```\n(.*?)```", README[i:], re.S).group(1)
    assert main(["friction", "--pa", "0.65", "--fe", "360"]) == 0
    assert capsys.readouterr().out == expected
