"""The operating point of an explore page: its text fields, their checks, the attractor search
under a time limit, and the rows of the attractor table. Pure Python, no browser.

The checks and the search are handed in by the CLI (:mod:`contactvib.cli.explore`): the page
shows the CLI's own one-line messages (its option names onto :mod:`contactvib.model.checks`) and
the CLI's search, and this package never imports the CLI."""

from __future__ import annotations

import shlex
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from contactvib.errors import ContactvibError
from contactvib.model.laws import DAMPING_NAMES, HUNT_CROSSLEY_DEFAULT, law_class, law_names
from contactvib.model.oscillator import PAPER_DEFAULTS, family_parameters

#: Every registered law's parameters (plug-ins included) but the power law's, which are the
#: model's own fields: (name, unit, default), the first law to declare a name giving its default.
LAW_PARAMETERS = {p.name: (p.unit, p.default) for n in law_names() if n != "power"
                  for p in reversed(law_class(n).parameters)}
#: The contact-law fields: the law and damping choosers (the CLI's ``--law``, ``--damping``),
#: the preload [N] (``--preload``, 0: none) and the parameters of the other laws and of the
#: Hunt–Crossley damping (``--set c_e``, ``lam``, ``c_lin``, ``gap_um``, …, ``alpha``) at their
#: defaults.
LAW_DEFAULTS = {"law": "power", "damping": "power", "preload": "0",
                **{k: f"{d:g}" for k, (_u, d) in LAW_PARAMETERS.items()}, "alpha": f"{HUNT_CROSSLEY_DEFAULT:g}"}
#: Text fields of the page (P_a/Q, f_e, the model parameters and the law fields) with their defaults.
DEFAULTS = {"pa": "0.65", "fe": "360", **{k: f"{v:g}" for k, v in PAPER_DEFAULTS.items()}, **LAW_DEFAULTS}
#: The model parameters the page may pass as ``--set`` (the CLI's ``SET_NAMES``), in its order.
MODEL_FIELDS = (*PAPER_DEFAULTS, *LAW_PARAMETERS, "alpha")
#: Default time limit of one computation [s].
TIME_LIMIT_S = 30.0


@dataclass
class Point:
    """The page's fields as typed (text); :meth:`checked` turns them into a model and excitation.

    ``law_file``: the table of ``--law table`` (the explore command's ``--law-file``; never
    from a URL, which must not name files on the server). The parameters of a family that is
    not chosen (``c_e`` under the power law, ``alpha`` under the power damping, …) are hidden in
    the page and ignored here: they are neither checked nor passed, so switching families back
    and forth keeps what was typed, and a hidden field can never block the page."""

    fields: dict[str, str] = field(default_factory=lambda: dict(DEFAULTS))
    law_file: str | None = None

    @classmethod
    def from_query(cls, query: dict, start: Point | None = None) -> Point:
        """The point of URL query parameters over ``start`` (the page's first point; default
        the paper's): unknown names ignored, values stay text, a law or damping the page does not
        offer is ignored."""
        start = cls() if start is None else start
        fields = dict(start.fields)
        choices = {"law": start.law_choices(), "damping": DAMPING_NAMES}
        for name in DEFAULTS:
            value = query.get(name)
            if isinstance(value, (list, tuple)):
                value = value[-1] if value else None
            if isinstance(value, bytes):
                value = value.decode("utf-8", "replace")
            if value is not None and (name not in choices or str(value) in choices[name]):
                fields[name] = str(value)[:64]
        return cls(fields, start.law_file)

    def law_choices(self) -> tuple[str, ...]:
        """The laws the page offers: power, exponential, and table with a ``law_file``."""
        return law_names() if self.law_file is not None else tuple(n for n in law_names() if n != "table")

    def query(self) -> dict[str, str]:
        """URL query parameters of the fields that differ from the defaults."""
        return {k: v for k, v in self.fields.items() if v != DEFAULTS[k]}

    def active(self) -> tuple[str, ...]:
        """The model fields of the chosen law and damping: M, g, S (every law's), the spring's, the
        damping's."""
        law, damping = self.fields["law"].strip(), self.fields["damping"].strip()
        families = family_parameters()
        return ("M", "g", "S", *families.get(law, ()), *families.get(f"damping {damping}", ()))

    def settings(self) -> tuple[str, ...]:
        """The model fields of the chosen families that differ from their defaults, as the CLI's
        ``--set NAME=VALUE``."""
        return tuple(f"{k}={self.fields[k].strip()}" for k in self.active()
                     if self.fields[k].strip() != DEFAULTS[k])

    def law_options(self) -> dict:
        """The CLI's law options (``--law``, ``--law-file``, ``--damping``, ``--preload``) as
        :func:`contactvib.cli.common.law_options` hands them to ``parse_model``; a preload of 0 is
        none."""
        law, preload = self.fields["law"].strip(), self.fields["preload"].strip()
        return {"law": law, "law_file": self.law_file if law == "table" else None,
                "damping": self.fields["damping"].strip(), "preload": None if preload == "0" else preload}

    def model_args(self) -> tuple[str, ...]:
        """The model as the CLI's arguments: the law options that differ from the defaults, then
        ``--set NAME=VALUE`` (:meth:`settings`)."""
        opts = self.law_options()
        args = [*(("--law", opts["law"]) if opts["law"] != "power" else ()),
                *(("--law-file", opts["law_file"]) if opts["law_file"] is not None else ()),
                *(("--damping", opts["damping"]) if opts["damping"] != "power" else ()),
                *(("--preload", opts["preload"]) if opts["preload"] is not None else ())]
        for s in self.settings():
            args += ["--set", s]
        return tuple(args)

    def command_options(self) -> str:
        """:meth:`model_args` as they follow a command on a shell line (each one quoted where the
        shell needs it), with a leading space; empty for the paper's model."""
        return "".join(f" {shlex.quote(a)}" for a in self.model_args())


class BadInput(ContactvibError, ValueError):
    """An input refused by the checks; its text is the CLI's one-line message."""


def derived(model) -> dict[str, float]:
    """f_n0 [Hz], y0 [µm] and ζ of a model, shown next to the fields."""
    return {"f_n0": model.f_n0, "y0": model.units.y_um, "zeta": model.zeta}


class Stopped(ContactvibError):
    """A computation stopped at the time limit."""


def run_limited(call, limit_s: float = TIME_LIMIT_S, flag: np.ndarray | None = None):
    """``call()`` with every kernel's stop flag set after ``limit_s`` (:func:`stop_scope`);
    raises :class:`Stopped` ("stopped after 30 s") when the limit stopped it. ``flag``: the
    stop flag (int64[1]; a new one when None) that another thread may also set to stop the call
    (then :class:`Stopped` "stopped"). A call that stops between kernel calls
    (:func:`contactvib.interrupts.check_interrupt`: the resonance sweeps) stops the same way."""
    from contactvib.interrupts import stop_scope

    flag = np.zeros(1, np.int64) if flag is None else flag
    timed_out = []
    timer = threading.Timer(limit_s, lambda: (timed_out.append(True), flag.__setitem__(0, 1)))
    timer.daemon = True
    timer.start()
    try:
        with stop_scope(flag):
            value = call()
    except KeyboardInterrupt:  # check_interrupt under the set flag
        if not flag[0]:
            raise
    finally:
        timer.cancel()
    if flag[0]:
        raise Stopped(f"stopped after {limit_s:g} s" if timed_out else "stopped")
    return value


def search(find, model, exc, limit_s: float = TIME_LIMIT_S):
    """``find(model, exc)`` (the CLI's default search) under the limit, and the seconds it took."""
    t0 = time.perf_counter()
    result = run_limited(lambda: find(model, exc), limit_s)
    return result, time.perf_counter() - t0


def _period(a) -> str:
    if a.period is None:
        return {"chaotic": "chaos", "quasi-periodic": "q-per"}.get(a.kind, "-")
    return str(a.period)


#: Harmonics of y(t) used to name a periodic orbit's resonance (as the sweep's rows hold).
N_HARMONICS = 64


def resonance_of(attractor, history, fn0_hz: float) -> str:
    """The resonance an attractor belongs to, named as the datasets name it
    (:func:`contactvib.labels.resonance_label`: "main", "1/3", "1/2 period-2",
    "subharmonic 1/2 bouncing", …; a non-periodic one by its type, "chaotic", …). The harmonics
    |Y_j| (frequency j f_e/k) come from one orbit period of ``history`` (sampled from phase 0,
    ``len(t) - 1`` samples per whole number of excitation periods)."""
    from contactvib.labels import dominant_ratio, resonance_label

    if attractor.period is None:
        return attractor.kind
    k, n_min = attractor.period, attractor.minima_per_period or 1
    y = np.asarray(history.y_um, float)
    n_periods = round(float(history.t_ms[-1] - history.t_ms[0]) * history.fe_hz / 1000.0)
    per = (y.size - 1) // max(n_periods, 1)  # samples per excitation period
    orbit = y[: per * k]
    harm = np.abs(np.fft.rfft(orbit))[1:N_HARMONICS + 1] * 2.0 / max(orbit.size, 1)
    nu = dominant_ratio(k, n_min, harm, attractor.loses_contact, history.fe_hz, fn0_hz)
    return resonance_label(0, k, nu, n_min, attractor.loses_contact, history.fe_hz, fn0_hz)


def table_rows(result, labels=None) -> list[dict]:
    """One row per attractor, as the CLI's table (full-precision numbers), with its resonance
    (``labels``, from :func:`resonance_of`) when given."""
    rows = [{"#": i, "period": _period(a),
             "minima": "-" if a.minima_per_period is None else str(a.minima_per_period),
             "A_pp [µm]": a.app_um, "y_min [µm]": a.ymin_um, "y_max [µm]": a.ymax_um,
             "gap [frac]": a.contact_loss_fraction,
             "|μ|max": a.floquet_abs_max, "basin": a.basin_fraction} for i, a in enumerate(result)]
    for row, label in zip(rows, labels or []):
        row["resonance"] = label
    return rows


#: The series' A_pp may differ from its attractor's by at most this fraction to be drawn on it.
SERIES_MATCH_RTOL = 1e-2


@dataclass(frozen=True)
class SeriesOverlay:
    """The perturbation series at the page's point (:func:`series_overlay`): ``series`` (a
    :class:`~contactvib.frequency.perturbation.PerturbationResult` or None), the index of the
    attractor it is drawn on (None: not drawn), and one line saying which, or why not."""

    series: object
    attractor: int | None
    note: str


def series_overlay(model, exc, result) -> SeriesOverlay:
    """The perturbation series (the CLI's ``perturbation`` defaults: 40 terms, Padé) and the
    attractor of ``result`` it describes (:func:`~contactvib.frequency.perturbation.described_attractor`),
    drawn only where the series is valid (contact kept, converged) and within
    :data:`SERIES_MATCH_RTOL` of that attractor's A_pp."""
    from contactvib.frequency.perturbation import described_attractor, perturbation_series
    from contactvib.model import ParameterError

    try:
        series = perturbation_series(exc)
    except (ParameterError, FloatingPointError, ZeroDivisionError, np.linalg.LinAlgError) as e:
        return SeriesOverlay(None, None, f"perturbation series not computed: {e}")
    head = f"perturbation series (N = {series.terms}, {series.summation})"
    if not series.valid:
        return SeriesOverlay(series, None, f"{head} not drawn: {series.reason}")
    if not len(result):
        return SeriesOverlay(series, None, f"{head} not drawn: no attractor to compare with")
    i = described_attractor(result, series)
    diff = abs(result[i].app_um - series.app_um) / series.app_um
    if diff > SERIES_MATCH_RTOL:
        return SeriesOverlay(series, None, f"{head} not drawn: A_pp {series.app_um:.5g} µm matches no "
                                           f"attractor (nearest #{i}, {result[i].app_um:.5g} µm)")
    return SeriesOverlay(series, i, f"{head} drawn on attractor #{i} (dashed red): A_pp {series.app_um:.6g} µm, "
                                    f"numerics {result[i].app_um:.6g} µm, relative difference {diff:.1e}")
