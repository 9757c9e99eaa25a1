"""Command-line interface (thin: parse, validate, call the public API, print, write).

Bad input stops before any computation with one line on stderr,
``contactvib: error: --fe (f_e) = -5: must be > 0 Hz``, and exit status 2. A computation that
cannot finish (:class:`~contactvib.ComputationError`) is one line naming its stage, exit status 1.
"""
from __future__ import annotations

import click

from contactvib.cli.atlas import atlas
from contactvib.cli.basins import basins
from contactvib.cli.common import InputError, RunInterrupted, one_line
from contactvib.cli.continuation import bifurcations, continue_, evolution
from contactvib.cli.explore import explore
from contactvib.cli.film import animate
from contactvib.cli.fit import fit
from contactvib.cli.frequency import hbm, perturbation
from contactvib.cli.friction import friction
from contactvib.cli.regimes import map_
from contactvib.cli.sections import orbit_diagram, section
from contactvib.cli.steady import attractors, simulate
from contactvib.cli.sweeps import paper, query, resonance
from contactvib.errors import ComputationError


class _Group(click.Group):
    """The command group: Ctrl-C anywhere in a command (parsing, computing, printing) becomes
    :class:`RunInterrupted`, i.e. the one line ``contactvib: interrupted`` and exit 130 (click
    would print an empty line first)."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            raise RunInterrupted("interrupted") from None


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="contactvib")
def cli():
    """contactvib: primary and superharmonic contact resonances (Kostek 2013).

    Units: y in µm (positive = contact deflection, negative = gap), ẏ in mm/s, t in ms,
    f in Hz, P_a in multiples of Q = M g. Defaults are the paper's parameters.
    """


for _command in (attractors, simulate, section, orbit_diagram, basins, resonance, atlas, query, paper, animate,
                 continue_, bifurcations, evolution, perturbation, hbm, map_, explore, friction, fit):
    cli.add_command(_command)


def _warning_line(message, category, filename, lineno, line=None) -> str:
    """Warnings of the library as one line each on stderr."""
    return f"contactvib: warning: {one_line(str(message))}\n"


def main(argv=None) -> int:
    """Entry point of the ``contactvib`` console script."""
    import warnings

    warnings.formatwarning = _warning_line
    try:
        rv = cli.main(args=argv, prog_name="contactvib", standalone_mode=False)
        return rv if isinstance(rv, int) else 0
    except InputError as e:
        click.echo(f"contactvib: error: {e}", err=True)
    except ComputationError as e:
        click.echo(f"contactvib: error: {e.stage} failed: {one_line(str(e))}", err=True)
        return 1
    except RunInterrupted as e:
        click.echo(f"contactvib: {e}", err=True)
        return 130
    except click.exceptions.Abort:
        click.echo("contactvib: interrupted", err=True)
        return 130
    except click.ClickException as e:
        click.echo(f"contactvib: error: {one_line(e.format_message())}", err=True)
    return 2



