"""Response to a random band-limited Gaussian force (``random_response``, ``simulate --random-psd``):
the force has the requested PSD, RMS and Gaussian statistics, a seed reproduces a run, the mean
contact force balances the static load W = Q + F_pre, and a small force gives the linear SDOF
response ∫ |H(f)|² S_F df."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.signal import welch
from scipy.stats import kurtosis, skew

from contactvib.model import ContactModel, ParameterError
from contactvib.steady.random_response import RandomForce, random_response

BAND = (200.0, 2000.0)


def _sf_for_rms(rms_n: float, band=BAND) -> float:
    """The flat one-sided PSD [N²/Hz] whose RMS over ``band`` is ``rms_n``."""
    return rms_n**2 / (band[1] - band[0])


def _linear_rms_um(model: ContactModel, sf: float, band=BAND) -> float:
    """RMS [µm] of the linear SDOF response: sqrt(∫ |H(f)|² S_F df), H = 1/(k − M ω² + i c ω)."""
    k, c, m = model.k_lin, model.c_lin, model.M

    def h2(f):
        w = 2.0 * math.pi * f
        return 1.0 / ((k - m * w * w) ** 2 + (c * w) ** 2)

    var, _ = quad(h2, *band, points=[model.f_n0], limit=500)
    return math.sqrt(var * sf) * 1e6


def test_seeded_reproducibility_and_dataset():
    """The same seed gives identical arrays; another seed another force; the dataset has units."""
    model = ContactModel()
    force = RandomForce(_sf_for_rms(0.3 * model.Q), *BAND, seed=7)
    a = random_response(model, force, 0.05)
    b = random_response(model, RandomForce(force.S_F, *BAND, seed=7), 0.05)
    for name in ("t_ms", "y_um", "ydot_mm_s", "force_n", "contact_force_n", "psd_um2_hz", "pdf_per_n"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.rms_um == b.rms_um and a.mean_contact_force_n == b.mean_contact_force_n
    other = RandomForce(force.S_F, *BAND, seed=8)
    assert not np.array_equal(force.components()[2], other.components()[2])
    ds = a.to_dataset()
    for var, unit in (("y_um", "um"), ("ydot_mm_s", "mm/s"), ("contact_force_n", "N"), ("force_n", "N"),
                      ("psd_um2_hz", "um^2/Hz"), ("pdf_per_n", "1/N"), ("t_ms", "ms"), ("psd_f_hz", "Hz")):
        assert ds[var].attrs["units"] == unit
    assert ds.attrs["static_load_n"] == pytest.approx(model.W)
    assert ds.sizes["time"] == a.t_ms.size


def test_force_rms_psd_and_gaussian():
    """Sample RMS = sqrt(S_F (f_hi − f_lo)) within 3 % over 2 s (the components' amplitudes are
    exact, only their cross terms fluctuate, ~1/sqrt(n)); the Welch PSD averaged over the band's
    interior = S_F within 5 % (16 Hz resolution, ~4 components per bin, 60 segments), below
    1e-3 S_F outside the band (but at DC); skewness and excess kurtosis 0 (Gaussian) within 5
    standard errors."""
    force = RandomForce(2e-4, *BAND, seed=3)
    fs = 8192.0
    t = np.arange(int(2.0 * fs)) / fs
    p = force.force_n(t)
    assert force.rms_n == pytest.approx(math.sqrt(2e-4 * 1800.0))
    assert np.std(p) == pytest.approx(force.rms_n, rel=0.03)
    assert abs(np.mean(p)) < 0.02 * force.rms_n
    f, psd = welch(p, fs=fs, nperseg=512)
    inside = (f > BAND[0] + 50.0) & (f < BAND[1] - 50.0)
    assert np.mean(psd[inside]) == pytest.approx(force.S_F, rel=0.05)
    assert np.median(psd[inside]) == pytest.approx(force.S_F, rel=0.15)
    outside = ((f > 40.0) & (f < BAND[0] - 100.0)) | (f > BAND[1] + 100.0)  # DC: the segments' means
    assert np.max(psd[outside]) < 1e-3 * force.S_F
    n_eff = 2.0 * 1800.0 * 2.0  # independent samples of a band-limited process: 2 B T
    assert abs(skew(p)) < 5.0 * math.sqrt(6.0 / n_eff)  # 5 standard errors: 0.14
    assert abs(kurtosis(p)) < 5.0 * math.sqrt(24.0 / n_eff)  # 0.29
    fj, aj, _ph = force.components()
    assert np.all(np.diff(fj) > 0) and fj[0] > BAND[0] and fj[-1] < BAND[1]
    assert np.sum(aj**2) / 2.0 == pytest.approx(force.S_F * 1800.0, rel=1e-12)


@pytest.mark.parametrize("model", [ContactModel(), ContactModel(preload=1.0)], ids=["paper", "preload"])
def test_kernel_forcing_is_the_force(model):
    """The kernels' spectrum excitation is 1 + P(t)/W at τ = ω_n0 t."""
    from contactvib._kernels.contact import forcing

    force = RandomForce(1e-4, *BAND, seed=1, n=64)
    par = force.kernel_parameters(model)
    t = np.array([0.0, 1e-4, 3.3e-3, 0.25])
    want = 1.0 + force.force_n(t) / model.W
    got = [forcing(ti * model.omega_n0, par) for ti in t]
    assert got == pytest.approx(want, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("model", [ContactModel(), ContactModel(preload=1.0)], ids=["paper", "preload"])
def test_mean_contact_force_is_the_static_load(model):
    """Force RMS 0.3 Q over 200–2000 Hz for 0.5 s (the slider bounces: contact loss): mean R = W
    = Q + F_pre within 3 batch-means standard errors; the force's sample RMS within 3 %."""
    force = RandomForce(_sf_for_rms(0.3 * model.Q), *BAND, seed=0)
    r = random_response(model, force, 0.5)
    assert 0.05 < r.contact_loss_probability < 0.8
    assert r.mean_contact_force_err_n > 0.0
    assert abs(r.mean_contact_force_n - model.W) <= 3.0 * r.mean_contact_force_err_n
    assert abs(r.mean_force_deviation) <= 3.0
    assert np.std(r.force_n) == pytest.approx(force.rms_n, rel=0.03)
    assert np.all(r.contact_force_n[r.y_um <= 0.0] == 0.0)
    assert np.sum(r.pdf_per_n * np.diff(r.pdf_edges_n)) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("model", [ContactModel(), ContactModel(preload=1.0, damping="hunt-crossley")],
                         ids=["paper", "preload-hunt-crossley"])
def test_small_force_gives_the_linear_response(model):
    """Response RMS 0.02 y0 (no contact loss, linear regime): RMS = sqrt(∫ |H|² S_F df) within
    10 % (measured: 0.6–1.7 % over seeds), and the PSD peaks at f_n0."""
    unit = _linear_rms_um(model, 1.0)
    sf = (0.02 * model.units.y_um / unit) ** 2
    r = random_response(model, RandomForce(sf, *BAND, seed=2), 0.5)
    predicted = _linear_rms_um(model, sf)
    assert r.contact_loss_probability == 0.0
    assert r.rms_um == pytest.approx(predicted, rel=0.10)
    assert r.psd_f_hz[np.argmax(r.psd_um2_hz)] == pytest.approx(model.f_n0, rel=0.03)
    assert r.mean_contact_force_n == pytest.approx(model.W, abs=3.0 * r.mean_contact_force_err_n)


@pytest.mark.parametrize("kwargs, symbol", [
    (dict(S_F=0.0), "S_F"),
    (dict(S_F=float("nan")), "S_F"),
    (dict(f_lo=0.0), "f_lo"),
    (dict(f_hi=100.0), "f_hi"),
    (dict(n=4), "n"),
    (dict(n=10**6), "n"),
    (dict(seed=-1), "seed"),
])
def test_bad_force_raises(kwargs, symbol):
    args = {"S_F": 1e-4, "f_lo": 200.0, "f_hi": 2000.0, **kwargs}
    with pytest.raises(ParameterError) as e:
        RandomForce(**args)
    assert e.value.symbol == symbol


@pytest.mark.parametrize("kwargs, symbol", [
    (dict(force=RandomForce(1e-4, 200.0, 1e6)), "f_hi"),
    (dict(force=RandomForce(1e12, 200.0, 2000.0)), "S_F"),
    (dict(duration_s=0.0), "duration"),
    (dict(duration_s=1e-4), "duration"),
    (dict(duration_s=1e5), "duration"),
    (dict(dt_sample_s=1e-3), "dt_sample"),
    (dict(discard_s=-1.0), "discard"),
    (dict(model="paper"), "model"),
    (dict(force=(1e-4, 200, 2000)), "force"),
])
def test_bad_response_input_raises(kwargs, symbol):
    args = {"model": ContactModel(), "force": RandomForce(1e-4, 200.0, 2000.0), "duration_s": 0.1, **kwargs}
    with pytest.raises(ParameterError) as e:
        random_response(**args)
    assert e.value.symbol == symbol


def test_cli_writes_dataset_and_figure(tmp_path, capsys):
    import xarray as xr

    from contactvib.cli import main
    from figure_files import assert_figure_file

    out = tmp_path / "rnd"
    assert main(["simulate", "--random-psd", "1e-4", "--band", "200", "2000", "--duration", "0.1",
                 "--seed", "4", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "contact loss probability" in text and "mean contact force" in text and "vs W" in text
    assert_figure_file(out / "random_response.png")
    with xr.open_dataset(out / "random.nc") as ds:
        assert ds["y_um"].attrs["units"] == "um"
        assert ds.attrs["seed"] == 4 and ds.attrs["S_F_n2_hz"] == 1e-4
        assert ds.sizes["time"] > 1000


@pytest.mark.parametrize("args, message", [
    (["--random-psd", "1e-4", "--band", "200", "2000", "--pa", "0.5"],
     "contactvib: error: --random-psd and --pa: give one of them"),
    (["--band", "200", "2000"], "contactvib: error: --band: belongs to a random force"),
    (["--random-psd", "1e-4", "--band", "2000", "200"], "contactvib: error: --band FHI (f_hi) = 200: must be >"),
    (["--random-psd", "0", "--band", "200", "2000"], "contactvib: error: --random-psd (S_F) = 0: must be > 0"),
])
def test_cli_bad_input_one_line(tmp_path, capsys, args, message):
    from contactvib.cli import main

    out = tmp_path / "bad"
    assert main(["simulate", *args, "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), captured.err
    assert not out.exists()
