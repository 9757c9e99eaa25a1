"""``python -m contactvib`` runs the command-line interface."""

import sys

from contactvib.cli import main

sys.exit(main())
