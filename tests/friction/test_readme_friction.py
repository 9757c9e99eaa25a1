"""The friction tutorial's printed table is what `contactvib friction --pa 0.65 --fe 360` prints."""

from contactvib.cli import main
from doc_pages import block_after


def test_friction_table_is_the_commands_output(capsys):
    expected = block_after("`contactvib friction --pa 0.65 --fe 360` (")
    assert main(["friction", "--pa", "0.65", "--fe", "360"]) == 0
    assert capsys.readouterr().out == expected
