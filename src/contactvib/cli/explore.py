"""CLI command ``explore``: the operating point live in the browser (:mod:`contactvib.explore`)."""

from __future__ import annotations

from contextlib import contextmanager
from functools import partial

import click

from contactvib.cli.common import (
    LAW_OPTIONS,
    InputError,
    RunInterrupted,
    feasible_frequencies,
    law_options,
    mapped_options,
    open_dataset_argument,
    parse_excitation,
    parse_int,
    parse_levels,
    parse_model,
    parse_positive,
)
from contactvib.cli.system import system_given, system_option


@contextmanager
def _law_of(point):
    """Within: the page's law options are the command's (``--law``, ``--law-file``,
    ``--damping``, ``--preload``, read by ``parse_model``), in this thread only."""
    token = LAW_OPTIONS.set(point.law_options())
    try:
        yield
    finally:
        LAW_OPTIONS.reset(token)


def _check(point):
    """The model and excitation of the page's fields, checked as ``attractors`` checks
    ``--law``, ``--damping``, ``--preload``, ``--set``, ``--pa`` and ``--fe`` (same one-line
    messages)."""
    from contactvib.explore.state import BadInput

    try:
        with _law_of(point):
            model = parse_model(point.settings())
        return model, parse_excitation(model, point.fields["pa"].strip(), None, point.fields["fe"].strip())
    except InputError as e:
        raise BadInput(f"contactvib: error: {e}") from None


#: The default options of ``contactvib attractors``: starts, seed, kmax, max periods, no seeds.
SEARCH_OPTIONS = ("512", "0", "8", "auto", False)


def _find(model, exc):
    """The search of ``contactvib attractors`` with its default options."""
    from contactvib.cli.steady import search_attractors as find
    from contactvib.explore.state import BadInput

    try:
        return find(model, exc, *SEARCH_OPTIONS)
    except InputError as e:
        raise BadInput(f"contactvib: error: {e}") from None
    except RunInterrupted as e:
        raise BadInput(f"contactvib: {e}") from None


#: Points per direction and shooting tolerance of the page's continuation (the CLI's
#: ``--max-points`` and ``--rtol``; ~5 s for the 1/4 at 0.65 Q, 360 Hz over 180–720 Hz, against
#: ~40 s with the CLI's defaults 2000 and 1e-12).
CONTINUATION_POINTS = 150
CONTINUATION_RTOL = "1e-10"


def _continue(point, model, exc, result, n):
    """The branch through attractor ``n`` of ``result`` in f_e, as ``contactvib continue``
    computes it over the page's window (:func:`contactvib.explore.continuation_view.window_hz`),
    and that command: ``(branch, command)``."""
    from contactvib.cli.continuation import continuation_settings
    from contactvib.continuation.diagram import continue_attractors
    from contactvib.errors import ComputationError
    from contactvib.explore.continuation_view import window_hz
    from contactvib.explore.state import BadInput

    lo, hi = (f"{v:.10g}" for v in window_hz(exc.f_e))
    command = (f"contactvib continue --pa {point.fields['pa'].strip()} --from-fe "
               f"{point.fields['fe'].strip()} --attractor {n} --no-switch --fmin {lo} --fmax {hi} "
               f"--max-points {CONTINUATION_POINTS} --rtol {CONTINUATION_RTOL}" + point.command_options())
    try:
        s = continuation_settings({"fmin": lo, "fmax": hi, "max_points": str(CONTINUATION_POINTS), "app_max": "2000",
                       "rtol": CONTINUATION_RTOL})
        branches = continue_attractors(model, pa_over_q=exc.pa_over_q, fe_hz=exc.f_e, attractor=n, settings=s,
                                       switch=False,
                                       attractors=result, parameter="f_e")
    except InputError as e:
        raise BadInput(f"contactvib: error: {e}") from None
    except (ComputationError, ValueError) as e:
        raise BadInput(f"contactvib: continuation failed: {e}") from None
    if not len(branches):
        raise BadInput(f"contactvib: attractor {n} is not a periodic orbit: nothing to continue")
    return branches[0], command


#: The options of the page's resonance graph (its grid), by SweepSettings' symbols.
_GRAPH_OPTIONS = {"f_min": "--graph-fmin", "f_max": "--graph-fmax", "df": "--graph-df"}


def _graph_grid(fmin, fmax, df) -> tuple[str, str, str]:
    """The grid of the page's resonance graph as typed (``--graph-fmin``, ``--graph-fmax``,
    ``--graph-df``), checked as ``resonance`` checks ``--fmin``, ``--fmax`` and ``--df`` (with the
    paper's model) before anything is served."""
    from contactvib.model import ContactModel
    from contactvib.sweeps.sweep import SweepSettings

    st = mapped_options(_GRAPH_OPTIONS, SweepSettings, fmin_hz=fmin, fmax_hz=fmax,
                 df_hz=parse_positive("--graph-df", "df", df, "Hz"))
    feasible_frequencies(ContactModel(), st.fmin_hz, st.fmax_hz, ("--graph-fmin", "--graph-fmax"))
    return fmin.strip(), fmax.strip(), df.strip()


def _level_inputs(point, grid):
    """The page's resonance graph as ``contactvib resonance --pa P_A --fmin .. --fmax .. --df ..
    [--law .. --damping .. --preload .. --set ..]`` computes it for one level (its other options
    at their defaults), checked as that command checks them (same one-line messages):
    ``(model, P_a [Q], SweepSettings, command)``."""
    from contactvib.cli.sweeps import resonance, sweep_inputs
    from contactvib.explore.state import BadInput

    fmin, fmax, df = grid
    pa = point.fields["pa"].strip()
    command = f"contactvib resonance --pa {pa} --fmin {fmin} --fmax {fmax} --df {df}" + point.command_options()
    sweep = {**{p.name: p.default for p in resonance.params}, "fmin": fmin, "fmax": fmax, "df": df,
             "settings": point.settings()}
    try:
        level = parse_levels((pa,))[0]
        with _law_of(point):
            model, st, _workers = sweep_inputs(sweep)
    except InputError as e:
        raise BadInput(f"contactvib: error: {e}") from None
    return model, level, st, command


def _start_point():
    """The page's first point: the paper's, with the command's law options (``--law``,
    ``--law-file``, ``--damping``, ``--preload``), checked as every command checks them before
    anything is served."""
    from contactvib.explore.state import Point

    opts = LAW_OPTIONS.get() or {}
    parse_model(())
    point = Point(law_file=opts.get("law_file"))
    point.fields.update(law=opts.get("law") or "power", damping=opts.get("damping") or "power")
    if opts.get("model_file") is not None:  # a saved model (contactvib fit --save-model)
        _model_fields(point, opts["model_file"])
    if opts.get("preload") is not None:
        point.fields["preload"] = opts["preload"].strip()
    return point


#: Seconds of warm-up after which the command says it is compiling.
WARM_NOTICE_S = 3.0


def _warm(point) -> None:
    """Compile the kernels of the page's first answer (the search at ``point`` and its time
    histories) once the server's port is bound and before it answers, so that no page's time
    limit counts the compilation: about 30 s once after an install (numba's cache), about a
    second after. A point the page will refuse is not warmed (the page shows the message)."""
    import threading

    from contactvib.cli.steady import search_attractors
    from contactvib.explore.state import BadInput
    from contactvib.steady.simulate import attractor_history

    notice = threading.Timer(WARM_NOTICE_S, lambda: click.echo(
        "contactvib explore: compiling the kernels (once after an install or an upgrade)...", err=True))
    notice.daemon = True
    notice.start()
    try:
        model, exc = _check(point)
        for attractor in search_attractors(model, exc, *SEARCH_OPTIONS):
            attractor_history(exc, attractor)
    except (BadInput, InputError):
        pass
    finally:
        notice.cancel()


def _model_fields(point, path) -> None:
    """The page's fields from a model file (``--model``): its law, damping, preload and
    parameters; a table law's rows cannot be fields (start with --law table --law-file)."""
    from contactvib.cli.common import read_model_file

    p = read_model_file(path)
    if "table" in p:
        raise InputError(f"--model = {path}: a table law's model: start explore with --law table --law-file FILE.csv")
    point.fields.update(law=str(p.get("law", "power")), damping=str(p.get("damping", "power")),
                        preload=repr(float(p.get("preload", 0.0))) if p.get("preload") else "0")
    for name, value in p.items():
        if name in point.fields and isinstance(value, (int, float)) and name != "preload":
            point.fields[name] = repr(float(value))


def _system_ops(label: str, has_q: bool):
    """(check, find, history) of a system's page (:mod:`contactvib.explore.system_page`): the
    fields read as ``attractors --system`` reads --pa (rocking, [Q]) or --pa-newton (a file, [N])
    and --fe, the search with its defaults, each attractor's history as ``simulate --system``."""
    import math

    from contactvib.cli.system import load_system_option, system_operating_point
    from contactvib.explore.state import BadInput

    system, model, _label = load_system_option(())

    def check(fields):
        pa, fe = fields["pa"].strip(), fields["fe"].strip()
        try:
            p, f, level = system_operating_point(model, label, pa if has_q else None, None if has_q else pa, fe)
        except InputError as e:
            raise BadInput(f"contactvib: error: {e}") from None
        return system, p, f, level

    def find(system, p, fe):
        from contactvib.steady.system_attractors import find_system_attractors

        return find_system_attractors(system, p, fe, nonperiodic=False, seeds=False)

    def history(system, p, fe, a):
        from contactvib.steady.system_orbits import simulate_system

        n = a.period * max(1, math.ceil(4 / a.period))
        return simulate_system(system, p, fe, a.orbit.z[:system.n], a.orbit.z[system.n:], n_periods=n)

    return system, (check, find, history)


def _serve_system(port, host, no_browser, limit, ready) -> None:
    """``explore --system``: the page of a structure with contacts (:mod:`contactvib.explore.system_page`)."""
    from contactvib.cli.system import system_label
    from contactvib.explore.server import serve
    from contactvib.explore.system_page import build_system_page

    label = system_label()
    has_q = label == "rocking"
    system, ops = _system_ops(label, has_q)
    modes = system.linear_modes()
    fields = {"pa": "0.5" if has_q else "0.1",
              "fe": "1300" if has_q else f"{float(modes[modes > 0][0]) if (modes > 0).any() else 1.0:.4g}"}
    serve(None, port, host, not no_browser, limit, ready,
          page=lambda: build_system_page(label, "Q" if has_q else "N", fields, ops, limit))


@click.command()
@system_option
@click.argument("dataset", required=False)
@click.option("--port", default="0", show_default=True, help="TCP port (0: a free one).")
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Interface to listen on; anything but 127.0.0.1 opens the page to the network.")
@click.option("--no-browser", is_flag=True, help="Do not open a browser; print the address.")
@click.option("--time-limit", default="30", show_default=True,
              help="Stop a computation after this many seconds.")
@click.option("--graph-fmin", default="30", show_default=True, metavar="HZ",
              help="Without DATASET: lowest f_e [Hz] of the resonance graph the page computes.")
@click.option("--graph-fmax", default="2000", show_default=True, metavar="HZ",
              help="Without DATASET: highest f_e [Hz] of that graph.")
@click.option("--graph-df", default="1", show_default=True, metavar="HZ",
              help="Without DATASET: frequency step [Hz] of that graph.")
@click.option("--graph-time-limit", default="300", show_default=True,
              help="Stop the computation of that graph after this many seconds.")
@law_options
def explore(dataset, port, host, no_browser, time_limit, graph_fmin, graph_fmax, graph_df,
            graph_time_limit):
    """The contact oscillator live in the browser: every attractor at the P_a and f_e you type.

    DATASET (optional): a paper.nc/resonance.nc/atlas.nc, or a folder holding one; the page then
    shows the resonance graph of each stored level, and a click on it moves f_e there. Without
    one, a button computes the graph of the current level in the background: the sweep of
    contactvib resonance from --graph-fmin to --graph-fmax, step --graph-df.

    --law, --law-file, --damping and --preload set the page's first contact law (the page's
    choosers change it; --law table needs --law-file, and only then does the page offer it)."""
    port = parse_int("--port", port, 0, 65535, symbol="port")
    limit = parse_positive("--time-limit", "time_limit", time_limit, "s")
    grid = _graph_grid(graph_fmin, graph_fmax, graph_df)
    graph_limit = parse_positive("--graph-time-limit", "time_limit", graph_time_limit, "s")
    start = _start_point()
    host = host.strip()
    if not host or any(c.isspace() for c in host):
        raise InputError(f"--host {host!r}: expected a host name or an address")
    if host not in ("127.0.0.1", "localhost"):
        click.echo(f"contactvib: warning: listening on {host}: the page is reachable from the network",
                   err=True)
    if system_given() and dataset is not None:
        raise InputError("--system and DATASET: a system's page shows its attractors; datasets belong to the slider")
    levels = None
    if dataset is not None:
        from contactvib.explore.dataset_view import DatasetLevels

        levels = DatasetLevels(open_dataset_argument(dataset))
    from contactvib.explore.server import serve

    def ready(url):
        click.echo(f"contactvib explore: {url} (Ctrl-C stops)", err=False)

    if system_given():
        try:
            return _serve_system(port, host, no_browser, limit, ready)
        except OSError as e:
            raise InputError(f"--port {port}: cannot listen on {host}:{port}: {e.strerror or e}") from None
        except KeyboardInterrupt:
            click.echo("contactvib: interrupted", err=True)
            return None
    try:
        ops = (_check, _find, _continue, partial(_level_inputs, grid=grid))
        serve(ops, port, host, not no_browser, limit, ready, levels, graph_limit, start, warm=partial(_warm, start))
    except OSError as e:
        raise InputError(f"--port {port}: cannot listen on {host}:{port}: {e.strerror or e}") from None
    except KeyboardInterrupt:
        click.echo("contactvib: interrupted", err=True)
