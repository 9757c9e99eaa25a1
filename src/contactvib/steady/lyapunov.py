"""Lyapunov spectra at one operating point: Benettin's QR method on the period map, Floquet
exponents of periodic orbits, the Kaplan–Yorke dimension and the attractor type they earn.

Method
    The stroboscopic map P advances the state (y, ẏ) — for a :class:`~contactvib.model.System`
    (q, q̇), 2n coordinates — by one excitation period T = 1/f_e; its Jacobian M_j = ∂P/∂z is the
    monodromy of one period from the variational equation, multiplied at every contact switch by
    the saltation matrix S = I + (f⁺ − f⁻) eₓᵀ / ẏ (:mod:`contactvib._kernels.flow`). Where the
    force is continuous at y = 0 — the power law with damping S h_n y^l ẏ, l > 0, and every law
    whose damping vanishes at y = 0 — f⁺ = f⁻ and S = I. An orthonormal frame is carried by
    M_j Q_j = Q_{j+1} R_j (Gram–Schmidt) over N periods in one compiled loop
    (:mod:`contactvib._kernels.lyapunov`); λ_i = Σ_j ln R_j[i, i] / (N T) [1/s], in
    :data:`BATCHES` batches whose means give the standard error of each exponent.
    A periodic orbit of period k has the exact exponents λ_i = ln ``|μ_i|`` / (k T) from its Floquet
    multipliers μ_i (:func:`floquet_spectrum`, standard error 0).

Damping identity
    det M_j = exp ∫ tr J dt over the period (det S = 1), and tr J = −S h_n y^l / M in contact, 0 in
    flight, so λ1 + λ2 = −⟨S h_n y^l / M⟩ (the time average over all time) exactly.
    ``damping_average_per_s`` is that average, integrated independently of the variational equation
    by Gauss–Legendre quadrature on the dense output along the same run. For a System the sum of
    all 2n exponents is −⟨tr(M⁻¹ C(t))⟩, C with each element's current contact damping.

Attractor type (the rule of the attractor search, factor :data:`SIGMA_FACTOR` = 3)
    chaotic when λ1 > 3 · stderr(λ1); quasi-periodic when ``|λ1|`` ≤ 3 · stderr(λ1) and the
    stroboscopic section is a closed curve (:func:`closed_curve`; k curves visited in turn for a
    period-k torus); periodic when the strobe sequence closes on a stable orbit.

Kaplan–Yorke dimension
    Of the attractor in the extended phase space (y, ẏ, phase): the map's exponents with the
    flow's zero exponent added, D = j + (λ1 + … + λj) / |λ_{j+1}|, j the largest index with a
    non-negative partial sum; given where λ1 > 0 (its stroboscopic section's dimension is D − 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.lyapunov import spectrum_map, system_spectrum_map
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib.errors import ComputationError
from contactvib.interrupts import new_stop_flag, run_interruptible
from contactvib.model import Excitation, ParameterError, check_excitation, check_int, check_range
from contactvib.steady.results import kaplan_yorke_dimension

__all__ = ["LyapunovSpectrum", "lyapunov_spectrum", "benettin_rows", "nearest_distances", "system_lyapunov_spectrum",
           "floquet_spectrum", "kaplan_yorke", "closed_curve", "system_benettin", "attractor_type", "check_periods",
           "SIGMA_FACTOR", "BATCHES", "MIN_PERIODS_PER_BATCH", "MIN_BATCHES", "PERIODS_DEFAULT"]

#: λ1 counts as non-zero beyond this many standard errors of its batch means.
SIGMA_FACTOR = 3.0
#: Batches of a Benettin run (the standard error is that of their means).
BATCHES = 20
#: Fewest batches, and fewest periods per batch, for an error bar.
MIN_BATCHES = 10
MIN_PERIODS_PER_BATCH = 10
#: Periods of a Benettin run by default.
PERIODS_DEFAULT = 20_000
#: Integrator tolerance of a Benettin run by default.
RTOL_DEFAULT = 1e-10
#: A closed curve: median gap between angle-ordered neighbours at most this many median
#: nearest-neighbour distances, and the largest gap at most CURVE_MAX_GAP of them.
CURVE_MEDIAN_GAP = 2.5
CURVE_MAX_GAP = 25.0


@dataclass(frozen=True)
class LyapunovSpectrum:
    """The Lyapunov spectrum of one trajectory of the period map.

    Attributes
    ----------
    exponents_per_s : ndarray
        λ_1 ≥ λ_2 ≥ … [1/s] (2 for the slider, 2n for a System).
    stderr_per_s : ndarray
        Standard error of each [1/s]: of the batch means (Benettin), 0 for Floquet exponents.
    fe_hz : float
        Excitation frequency [Hz]; per excitation period: ``exponents_per_period``.
    periods : int
        Excitation periods averaged (Floquet: the orbit's period k).
    transient_periods : int
        Periods integrated before the average.
    batches : int
        Batches of the average (1 for Floquet).
    method : str
        ``"benettin"`` or ``"floquet"``.
    damping_average_per_s : float
        −⟨S h_n y^l / M⟩ [1/s] (the Liouville trace: −⟨tr M⁻¹C(t)⟩ for a System), integrated on
        the dense output along the run; equals Σλ_i. NaN where not computed.
    damping_stderr_per_s : float
        Its standard error from the batch means [1/s].
    contact_fraction : float
        Fraction of the averaged time with the contact closed [1] (NaN where not computed).
    state : ndarray
        The state at the end of the run (nondimensional for the slider, scaled for a System).
    """

    exponents_per_s: np.ndarray
    stderr_per_s: np.ndarray
    fe_hz: float
    periods: int
    transient_periods: int = 0
    batches: int = 1
    method: str = "benettin"
    damping_average_per_s: float = math.nan
    damping_stderr_per_s: float = math.nan
    contact_fraction: float = math.nan
    state: np.ndarray = field(default_factory=lambda: np.empty(0), repr=False)

    @property
    def exponents_per_period(self) -> np.ndarray:
        """λ_i [1/excitation period] = λ_i [1/s] / f_e."""
        return self.exponents_per_s / self.fe_hz

    @property
    def sum_per_s(self) -> float:
        """Σ λ_i [1/s]."""
        return float(np.sum(self.exponents_per_s))

    @property
    def kaplan_yorke_dimension(self) -> float | None:
        """The Kaplan–Yorke dimension of the exponents (``kaplan_yorke``; None unless λ1 > 0)."""
        return kaplan_yorke(self.exponents_per_s)

    @property
    def attractor_type(self) -> str:
        """"chaotic" when λ1 > SIGMA_FACTOR · stderr, else "periodic" (Floquet) or "quasi-periodic"
        where ``|λ1|`` ≤ SIGMA_FACTOR · stderr, "converging" below (the section's shape is not tested here:
        ``attractor_type``)."""
        return attractor_type(self)

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib lyapunov --json`` for one spectrum."""
        ky = self.kaplan_yorke_dimension
        return {"method": self.method, "lyapunov_per_s": [float(v) for v in self.exponents_per_s],
                "lyapunov_stderr_per_s": [float(v) for v in self.stderr_per_s],
                "lyapunov_per_period": [float(v) for v in self.exponents_per_period],
                "kaplan_yorke_dimension": ky, "sum_per_s": self.sum_per_s,
                "damping_average_per_s": _number(self.damping_average_per_s),
                "damping_stderr_per_s": _number(self.damping_stderr_per_s),
                "contact_fraction": _number(self.contact_fraction), "periods": int(self.periods),
                "transient_periods": int(self.transient_periods), "batches": int(self.batches),
                "fe_hz": float(self.fe_hz)}


def _number(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def attractor_type(spec: LyapunovSpectrum, factor: float = SIGMA_FACTOR) -> str:
    """The type the spectrum alone earns: "periodic" (Floquet), "chaotic" (λ1 > factor · stderr),
    "quasi-periodic" (``|λ1|`` ≤ factor · stderr: a torus if its section is a closed curve) or
    "converging" (λ1 < −factor · stderr)."""
    if spec.method == "floquet":
        return "periodic"
    lam, se = float(spec.exponents_per_s[0]), float(spec.stderr_per_s[0])
    if lam > factor * se:
        return "chaotic"
    return "quasi-periodic" if lam >= -factor * se else "converging"


def kaplan_yorke(exponents) -> float | None:
    """Kaplan–Yorke dimension of the flow's attractor from the map's exponents (any units, any
    order): the flow's zero exponent added, D = j + Σ_{i≤j} λ_i / |λ_{j+1}|; None unless λ1 > 0
    (:func:`contactvib.steady.results.kaplan_yorke_dimension`)."""
    return kaplan_yorke_dimension(exponents)


def floquet_spectrum(multipliers, k: int, fe_hz: float, state=None) -> LyapunovSpectrum:
    """The exponents ln ``|μ_i|`` / (k T) [1/s] of a period-k orbit (T = 1/f_e) from its Floquet
    multipliers, descending; standard errors 0 (no damping average: it would be Σλ_i itself)."""
    mu = np.abs(np.asarray(multipliers, complex))
    lam = np.sort(np.log(mu) * fe_hz / k)[::-1]
    return LyapunovSpectrum(exponents_per_s=lam, stderr_per_s=np.zeros(lam.size), fe_hz=float(fe_hz),
                            periods=int(k), method="floquet",
                            state=np.asarray(state if state is not None else np.empty(0), float))


def check_periods(periods, batches) -> tuple[int, int]:
    """``(periods, batches)`` checked: at least :data:`MIN_BATCHES` batches of at least
    :data:`MIN_PERIODS_PER_BATCH` periods each, for an error bar."""
    batches = check_int("batches", batches, MIN_BATCHES, 10_000)
    periods = check_int("periods", periods, MIN_BATCHES * MIN_PERIODS_PER_BATCH, 100_000_000)
    if periods < batches * MIN_PERIODS_PER_BATCH:
        raise ParameterError("periods", periods, f"must be ≥ {MIN_PERIODS_PER_BATCH} × batches = "
                             f"{batches * MIN_PERIODS_PER_BATCH} for an error bar ({MIN_PERIODS_PER_BATCH} "
                             f"periods per batch; fewer batches, at least {MIN_BATCHES}, need fewer)",
                             bounds=("batches",))
    return periods, batches


def _batch_stats(logs: np.ndarray, seconds: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean and standard error [1/s] of each column of per-batch sums ``logs`` (each over
    ``seconds``), sorted by the mean, descending; and the order."""
    per = logs / seconds
    mean = per.mean(axis=0)
    se = per.std(axis=0, ddof=1) / math.sqrt(per.shape[0])
    order = np.argsort(-mean, kind="stable")
    return mean[order], se[order], order


def benettin(excitation: Excitation, z, periods: int, batches: int, transient: int = 0,
             rtol: float = RTOL_DEFAULT, with_trace: bool = True,
             strobe: np.ndarray | None = None) -> LyapunovSpectrum:
    """:func:`~contactvib._kernels.lyapunov.spectrum_map` from the nondimensional ``z`` (phase 0):
    ``batches`` batches of ``periods // batches`` periods after ``transient`` periods; ``strobe``
    (float[m, 2], m ≤ the periods averaged), if given, receives the run's last m strobe points."""
    per_batch = periods // batches
    strobe = np.empty((0, 2)) if strobe is None else strobe
    logs = np.zeros((batches, 2))
    trace = np.zeros(batches)
    out = np.zeros(3)
    stop = new_stop_flag()
    st = run_interruptible(spectrum_map, np.asarray(z, float).copy(), excitation.kernel_parameters(), float(rtol),
                           int(transient), int(batches), int(per_batch), bool(with_trace), logs, trace, out, strobe,
                           stop, stop=stop)
    if st != STATUS_OK:
        raise ComputationError(f"the Lyapunov spectrum's integration failed ({status_message(st)})",
                               stage="integration")
    return _benettin_result(excitation.f_e, per_batch, batches, transient, logs, trace, out)


def _benettin_result(fe: float, per_batch: int, batches: int, transient: int, logs: np.ndarray,
                     trace: np.ndarray, out: np.ndarray) -> LyapunovSpectrum:
    """The spectrum of one :func:`~contactvib._kernels.lyapunov.spectrum_map` run at f_e = ``fe``
    [Hz] from its outputs ``logs`` (batches, 2), ``trace`` (batches) and ``out`` (3)."""
    seconds = per_batch / fe
    mean, se, _ = _batch_stats(logs, seconds)
    tr = trace / seconds
    return LyapunovSpectrum(exponents_per_s=mean, stderr_per_s=se, fe_hz=fe, periods=per_batch * batches,
                            transient_periods=int(transient), batches=int(batches),
                            damping_average_per_s=float(tr.mean()),
                            damping_stderr_per_s=float(tr.std(ddof=1) / math.sqrt(batches)),
                            contact_fraction=float(out[2]), state=out[:2].copy())


def benettin_rows(excitations, Z, periods: int, batches: int, rtol: float = RTOL_DEFAULT,
                  strobe: int = 0) -> tuple[list, np.ndarray]:
    """:func:`benettin` (no transient, no trace quadrature) from each nondimensional row of ``Z``
    (N, 2; phase 0) at the operating point ``excitations[q]``, all rows in one compiled call
    (:func:`~contactvib._kernels.lyapunov.spectrum_map_rows`, on this process's numba threads).
    Returns the spectra (None where the integration failed: :func:`benettin` would raise) and the
    runs' last ``strobe`` strobe points (N, strobe, 2); each row exactly as :func:`benettin`'s."""
    from contactvib._kernels.lyapunov import spectrum_map_rows

    n = len(excitations)
    per_batch = periods // batches
    Z = np.ascontiguousarray(np.asarray(Z, float).reshape(n, 2))
    logs = np.zeros((n, batches, 2))
    trace = np.zeros((n, batches))
    out = np.zeros((n, 3))
    after = np.empty((n, strobe, 2))
    status = np.zeros(n, np.int64)
    pars = [e.kernel_parameters() for e in excitations]
    stop = new_stop_flag()
    for size in sorted({p.shape[0] for p in pars}):  # one call per parameter-vector length (law family)
        rows = np.array([q for q in range(n) if pars[q].shape[0] == size], np.int64)
        sub = [np.ascontiguousarray(a[rows]) for a in (logs, trace, out, after, status)]
        run_interruptible(spectrum_map_rows, np.ascontiguousarray(Z[rows]), np.stack([pars[q] for q in rows]),
                          float(rtol), np.int64(batches), np.int64(per_batch), *sub, stop, stop=stop)
        for a, b in zip((logs, trace, out, after, status), sub):
            a[rows] = b
    specs = [_benettin_result(excitations[q].f_e, per_batch, batches, 0, logs[q], trace[q], out[q])
             if status[q] == STATUS_OK else None for q in range(n)]
    return specs, after


def lyapunov_spectrum(excitation: Excitation, state=None, *, periods: int = PERIODS_DEFAULT,
                      transient_periods: int | None = None, batches: int = BATCHES,
                      rtol: float = RTOL_DEFAULT, method: str = "auto") -> LyapunovSpectrum:
    """The Lyapunov spectrum [1/s] of the slider's period map at the operating point ``excitation``.

    Parameters
    ----------
    excitation : Excitation
        The operating point (its model: ``excitation.model``).
    state : Attractor, (y_um, ydot_mm_s) or None
        Where to start, at phase 0: an attractor of ``find_attractors`` (a periodic
        one gives its Floquet exponents unless ``method="benettin"``), a state y [µm], ẏ [mm/s],
        or None: the static equilibrium.
    periods : int
        Excitation periods of the Benettin average (≥ batches × 10).
    transient_periods : int or None
        Periods integrated first; None: 0 from an attractor, else 2000.
    batches : int
        Batches for the standard errors (≥ 10).
    rtol : float
        Integrator tolerance (1e-14 … 1e-6).
    method : str
        "auto", "benettin" or "floquet" (a periodic attractor only).
    """
    model = check_excitation(excitation).model
    periods, batches = check_periods(periods, batches)
    rtol = check_range("rtol", rtol, 1e-14, True, upper=1e-6)
    if method not in ("auto", "benettin", "floquet"):
        raise ParameterError("method", method, "must be one of auto, benettin, floquet")
    period = getattr(state, "period", None)
    if hasattr(state, "state") and hasattr(state, "floquet_multipliers"):
        z = np.asarray(state.state, float)
        default_transient = 0
    elif state is None:
        z, default_transient = np.array([1.0, 0.0]), 2000
        period = None
    else:
        y_um, ydot = (float(v) for v in state)
        z, default_transient = np.array(model.units.state(y_um, ydot)), 2000
        period = None
    if method == "floquet" and period is None:
        raise ParameterError("method", method, "floquet needs a periodic attractor as the state")
    if period is not None and method != "benettin":
        return floquet_spectrum(state.floquet_multipliers, period, excitation.f_e, z)
    transient = default_transient if transient_periods is None else check_int("transient_periods",
                                                                               transient_periods, 0, 100_000_000)
    return benettin(excitation, z, periods, batches, transient, rtol)


def system_lyapunov_spectrum(system, pa_newton: float, fe_hz: float, state=None, *,
                             periods: int = PERIODS_DEFAULT, transient_periods: int | None = None,
                             batches: int = BATCHES, rtol: float = RTOL_DEFAULT,
                             with_trace: bool = False) -> LyapunovSpectrum:
    """The 2n exponents [1/s] of a System's period map under P_a cos(2π f_e t) (P_a = ``pa_newton``
    [N]) by Benettin's method (``lyapunov_spectrum``'s options); ``state``: a
    ``SystemAttractor`` (a periodic one: its Floquet exponents; another: from its SI state, no
    transient by default), an SI state (q, q̇) of length 2n, or None: the static state. ``state`` of
    the result is scaled (``system.kernel_form(...).scales``). ``with_trace``: also the damping
    average −⟨tr M⁻¹C(t)⟩ and the contact fraction (:func:`system_benettin`)."""
    from contactvib._kernels.system_flow import system_arrays
    from contactvib.model.system import System
    from contactvib.model.system import check_excitation as check_system_excitation

    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    pa, fe = check_system_excitation(pa_newton, fe_hz)
    periods, batches = check_periods(periods, batches)
    rtol = check_range("rtol", rtol, 1e-14, True, upper=1e-6)
    if getattr(state, "orbit", None) is not None:
        return floquet_spectrum(state.floquet_multipliers, state.period, fe, state.orbit.z)
    form = system.kernel_form(pa, fe)
    sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
    if state is None:
        z_si, default_transient = np.concatenate([system.static_state(), np.zeros(system.n)]), 2000
    elif hasattr(state, "orbit"):
        z_si, default_transient = np.asarray(state.state, float), 0
    else:
        z_si, default_transient = np.asarray(state, float).reshape(2 * system.n), 2000
    transient = default_transient if transient_periods is None else check_int("transient_periods",
                                                                               transient_periods, 0, 100_000_000)
    return system_benettin(sa, form.scales.to_scaled(z_si), fe, periods, batches, transient, rtol, with_trace)


def system_benettin(sa, x, fe_hz: float, periods: int, batches: int, transient: int = 0,
                    rtol: float = RTOL_DEFAULT, with_trace: bool = False,
                    strobe: np.ndarray | None = None) -> LyapunovSpectrum:
    """:func:`~contactvib._kernels.lyapunov.system_spectrum_map` on the compiled system ``sa`` from
    the scaled state ``x`` (phase 0): ``batches`` batches of ``periods // batches`` periods after
    ``transient`` periods. ``with_trace``: the damping average −⟨tr M⁻¹C(t)⟩ [1/s] with its standard
    error, and as ``contact_fraction`` the largest fraction of time one contact is closed (0 without
    contacts); ``strobe`` (float[m, 2n], m ≤ the periods averaged), if given, receives the run's
    last m scaled strobe points."""
    per_batch = periods // batches
    n2 = len(x)
    strobe = np.empty((0, n2)) if strobe is None else strobe
    logs, trace, out = np.zeros((batches, n2)), np.zeros(batches), np.zeros(n2)
    contact, stop = np.zeros(sa.U.shape[0]), new_stop_flag()
    st = run_interruptible(system_spectrum_map, sa, np.ascontiguousarray(x, float), float(rtol), int(transient),
                           int(batches), int(per_batch), bool(with_trace), logs, trace, out, contact, strobe,
                           stop, stop=stop)
    if st != STATUS_OK:
        raise ComputationError(f"the Lyapunov spectrum's integration failed ({status_message(st)})",
                               stage="integration")
    seconds = per_batch / fe_hz
    mean, se, _ = _batch_stats(logs, seconds)
    tr = trace / seconds
    frac = float(np.max(contact)) if contact.size else (0.0 if with_trace else math.nan)
    return LyapunovSpectrum(exponents_per_s=mean, stderr_per_s=se, fe_hz=fe_hz, periods=per_batch * batches,
                            transient_periods=int(transient), batches=int(batches), state=out,
                            damping_average_per_s=float(tr.mean()) if with_trace else math.nan,
                            damping_stderr_per_s=float(tr.std(ddof=1) / math.sqrt(batches)) if with_trace
                            else math.nan, contact_fraction=frac)


def nearest_distances(p: np.ndarray) -> np.ndarray:
    """The distance np.hypot(dx, dy) of each point of ``p`` (n ≥ 2, 2) to its nearest other point:
    exactly ``min_j≠i hypot(p_i − p_j)`` of the full n × n matrix, the hypot evaluated only for the
    candidates of :func:`~contactvib._kernels.lyapunov.nearest_candidates`."""
    from contactvib._kernels.lyapunov import nearest_candidates

    p = np.ascontiguousarray(p, dtype=float)
    n = p.shape[0]
    counts = np.zeros(n, np.int64)
    js = np.empty(4 * n, np.int64)
    m = nearest_candidates(p, counts, js)
    if m > js.shape[0]:
        js = np.empty(m, np.int64)
        nearest_candidates(p, counts, js)
    js = js[:m]
    ii = np.repeat(np.arange(n), counts)
    d = np.hypot(p[ii, 0] - p[js, 0], p[ii, 1] - p[js, 1])
    return np.minimum.reduceat(d, np.concatenate([[0], np.cumsum(counts)[:-1]]))


def _one_curve(p: np.ndarray) -> bool:
    """Whether the points ``p`` (m, 2), scaled to unit extent, lie on one closed curve about their
    centroid: ordered by angle, successive points are near neighbours."""
    c = p - p.mean(axis=0)
    order = np.argsort(np.arctan2(c[:, 1], c[:, 0]))
    q = p[order]
    gaps = np.hypot(*(np.roll(q, -1, axis=0) - q).T)
    nn = float(np.median(nearest_distances(p)))
    if not nn > 0.0:
        return False
    return bool(np.median(gaps) <= CURVE_MEDIAN_GAP * nn and gaps.max() <= CURVE_MAX_GAP * nn)


def closed_curve(points, max_curves: int = 8) -> int:
    """The number k ≤ ``max_curves`` of closed curves the stroboscopic points (float[N, 2], in
    time order) visit in turn — each k-th point on one closed curve about its centroid
    (:func:`_one_curve`) — or 0 when they are not on closed curves (a cloud, a periodic orbit's
    few points). Needs at least 16 points per curve."""
    pts = np.asarray(points, float)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    ext = np.ptp(pts, axis=0) if pts.size else np.zeros(2)
    if pts.shape[0] < 16 or not np.all(ext > 0.0):
        return 0
    pts = pts / ext
    for k in range(1, max_curves + 1):
        if pts.shape[0] < 16 * k:
            break
        parts = [pts[j::k] for j in range(k)]
        if all(np.ptp(p, axis=0).max() > 1e-9 and _one_curve(p) for p in parts):
            return k
    return 0
