"""The README's printed examples are what the commands print today (so its numbers cannot drift)."""

from __future__ import annotations

import re
from pathlib import Path

from contactvib.cli import main

README = (Path(__file__).resolve().parents[2] / "README.md").read_text()


def _block_after(heading: str) -> str:
    """The first fenced block after a heading line of the README."""
    i = README.index(heading)
    m = re.search(r"```\n(.*?)```", README[i:], re.S)
    return m.group(1)


def test_attractors_table_at_360_hz_is_the_commands_output(capsys):
    expected = _block_after("### Output of `contactvib attractors --pa 0.65 --fe 360`")
    assert main(["attractors", "--pa", "0.65", "--fe", "360"]) == 0
    assert capsys.readouterr().out == expected
