"""``python -m contactvib`` and the ``contactvib`` console script: the command-line interface.

:func:`main` imports the commands itself, so that Ctrl-C while they load (``import contactvib``
before it loads nothing heavy) gives the same one line ``contactvib: interrupted`` and exit
130 as a Ctrl-C later."""

import sys


def main(argv=None) -> int:
    """Run ``contactvib`` with ``argv`` (default: the command line); the exit status."""
    try:
        from contactvib.cli.main import main as run
    except KeyboardInterrupt:
        sys.stderr.write("contactvib: interrupted\n")
        return 130
    return run(argv)


if __name__ == "__main__":
    sys.exit(main())
