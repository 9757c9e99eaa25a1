"""The README's printed examples are what the commands print today (so its numbers cannot drift);
the attractors tutorial prints the same table."""

from __future__ import annotations

from contactvib.cli import main
from doc_pages import DOCS, README, block_after

HEADING = "Output of `contactvib attractors --pa 0.65 --fe 360`"


def test_attractors_table_at_360_hz_is_the_commands_output(capsys):
    expected = block_after("### " + HEADING, README)
    assert block_after("## " + HEADING, DOCS / "tutorials" / "attractors.md") == expected
    assert main(["attractors", "--pa", "0.65", "--fe", "360"]) == 0
    assert capsys.readouterr().out == expected
