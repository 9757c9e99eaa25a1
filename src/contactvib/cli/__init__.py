"""The ``contactvib`` command line (thin: parse, call the public API, print, write)."""

from contactvib.cli.main import cli, main

__all__ = ["cli", "main"]
