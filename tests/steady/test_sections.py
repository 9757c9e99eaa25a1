"""Poincaré sections, impact maps and orbit diagrams against independent references: the refined
orbits' own strobe points, scipy's solve_ivp with located contact events (contactvib.testing)."""

import math

import numpy as np
import pytest

from contactvib import ContactModel, Excitation, find_attractors
from contactvib.model import ParameterError
from contactvib.steady.orbit_diagram import MAX_GRID_POINTS, OrbitDiagramSettings, orbit_diagram, write_csv
from contactvib.steady.sections import largest_exponent, poincare_sections, trajectory_points
from contactvib.testing import integrate_modes, power_law_rhs


@pytest.fixture(scope="module")
def found_360():
    exc = Excitation(ContactModel(), 0.65, 360.0)
    return exc, find_attractors(exc, n_starts=128)


def test_periodic_sections_are_the_orbits_strobe_points(found_360):
    """A period-k orbit's section is its k strobe points (refined at 1e-12) to 1e-6 µm, 1e-5 mm/s."""
    exc, found = found_360
    sections = poincare_sections(exc, found, n_periods=50)
    assert len(sections) == len(found) >= 4
    for a, s in zip(found, sections):
        assert a.period is not None and s.period == a.period
        assert s.y_um.size == a.period
        assert s.label == f"period {a.period}: {a.period} point{'s' if a.period > 1 else ''}"
        np.testing.assert_allclose(s.y_um, a.strobe_y_um, rtol=0, atol=1e-6)
        np.testing.assert_allclose(s.ydot_mm_s, a.strobe_ydot_mm_s, rtol=0, atol=1e-5)
        # λ1 of a periodic orbit: ln max|mu| per excitation period, from its Floquet multipliers
        assert s.lambda1 == pytest.approx(math.log(a.floquet_abs_max) / a.period, rel=1e-12)
        assert s.lambda1 < 0


def test_strobe_points_and_contact_losses_match_scipy():
    """A trajectory at 0.75 Q, 816.5 Hz (losing contact every period): its strobe points and the
    velocities at its contact losses agree with solve_ivp (DOP853, rtol 1e-12, located switches)
    to 1e-6 (nondimensional: y0, y0 ω_n0) over 6 periods."""
    exc = Excitation(ContactModel(), 0.75, 816.5)
    z0 = np.array([0.5, -1.0])
    n = 6
    pts = trajectory_points(exc, z0, n, rtol=1e-12)
    par = exc.kernel_parameters()
    fc, ff = power_law_rhs(par)
    T = exc.tau_period
    ref = [z0]
    losses = []
    z = z0
    for k in range(n):
        tr = integrate_modes(fc, ff, z, k * T, (k + 1) * T, rtol=1e-12, atol=1e-12)
        ends = tr.ends
        for (mode, (_ta, tb), _sol), end in zip(tr.segments, ends):
            if mode and tb < (k + 1) * T - 1e-9:  # a contact segment ended by the switch to flight
                losses.append((tb, end[1]))
        z = tr.y
        ref.append(z)
    ref = np.array(ref[:n])
    np.testing.assert_allclose(pts.strobe, ref, rtol=0, atol=1e-6)
    assert pts.loss_tau.size == len(losses) >= n - 1
    np.testing.assert_allclose(pts.loss_tau, [t for t, _ in losses], rtol=0, atol=1e-7)
    np.testing.assert_allclose(pts.loss_v, [v for _, v in losses], rtol=0, atol=1e-6)
    assert np.all(pts.loss_v < 0)


def test_chaotic_section_is_a_cloud_with_positive_lambda1():
    """The small-basin chaotic attractor at 0.75 Q, 816.5 Hz: a cloud of N distinct points, λ1 > 0.02."""
    exc = Excitation(ContactModel(), 0.75, 816.5)
    found = find_attractors(exc, n_starts=512)
    chaotic = [i for i, a in enumerate(found) if a.kind == "chaotic"]
    assert chaotic
    s = poincare_sections(exc, found, n_periods=200)[chaotic[0]]
    assert s.y_um.size == 200 and np.unique(np.round(s.y_um, 9)).size == 200
    assert s.lambda1 > 0.02
    assert s.loss_phase_rad.size > 100
    assert np.all((s.loss_phase_rad >= 0) & (s.loss_phase_rad < 2 * np.pi))
    assert largest_exponent(exc, found[chaotic[0]].state) > 0.02


def test_section_csv_has_units_and_one_row_per_point(found_360, tmp_path):
    exc, found = found_360
    sections = poincare_sections(exc, found, n_periods=10)
    path = sections.to_csv(tmp_path / "s.csv", impacts=True)
    lines = path.read_text().splitlines()
    assert lines[0].startswith("#") and "units" in lines[1] and "[um]" in lines[1]
    assert lines[2].split(",")[:6] == ["attractor", "kind", "map", "period", "k", "y_um"]
    n_section = sum(s.y_um.size for s in sections)
    n_impact = sum(s.loss_phase_rad.size for s in sections)
    assert len(lines) - 3 == n_section + n_impact


def test_orbit_diagram_period_one_and_two():
    """0.65 Q, 358–362 Hz: every attractor is periodic; each contributes exactly `period` strobe
    points per f_e, and at 360 Hz these are the search's strobe points (1e-6 µm)."""
    model = ContactModel()
    st = OrbitDiagramSettings(vary="fe", start=358.0, stop=362.0, step=2.0, n_periods=16, search_every=10,
                              n_starts=128)
    ds = orbit_diagram(model, pa_over_q=0.65, settings=st)
    assert set(ds["period"].values.tolist()) >= {1, 2}
    for (g, a), n in ds.groupby(["grid_index", "attractor"]).count()["y_um"].to_series().items():
        sel = (ds["grid_index"].values == g) & (ds["attractor"].values == a)
        assert n == ds["period"].values[sel][0]
    at360 = ds.where(ds["fe_hz"] == 360.0, drop=True)
    found = find_attractors(Excitation(model, 0.65, 360.0), n_starts=128)
    for att in found:
        for y in att.strobe_y_um:
            assert np.min(np.abs(at360["y_um"].values - y)) < 1e-6


def test_orbit_diagram_dataset_roundtrip(tmp_path):
    ds = orbit_diagram(ContactModel(), pa_over_q=0.65,
                       settings=OrbitDiagramSettings(start=360.0, stop=361.0, step=1.0, n_periods=8, n_starts=32))
    assert ds["y_um"].attrs["units"] == "um" and ds["lambda1"].attrs["units"] == "1/excitation period"
    ds.to_netcdf(tmp_path / "d.nc")
    import xarray as xr

    with xr.open_dataset(tmp_path / "d.nc") as back:
        np.testing.assert_array_equal(back["y_um"].values, ds["y_um"].values)
    write_csv(ds, tmp_path / "d.csv")
    lines = (tmp_path / "d.csv").read_text().splitlines()
    assert len(lines) == 3 + ds.sizes["point"]
    write_csv(ds, tmp_path / "v.csv", "v-loss")
    assert len((tmp_path / "v.csv").read_text().splitlines()) == 3 + ds.sizes["loss"]


@pytest.mark.parametrize("kw, symbol", [
    ({"start": 820.0, "stop": 810.0}, "f_to"),
    ({"step": 0.0}, "df"),
    ({"step": -1.0}, "df"),
    ({"start": 1.0, "stop": 1e6, "step": 1.0}, "df"),
    ({"n_periods": 1}, "n_periods"),
    ({"search_every": 0}, "search_every"),
    ({"vary": "m2"}, "vary"),
])
def test_orbit_diagram_settings_refused(kw, symbol):
    with pytest.raises(ParameterError) as e:
        OrbitDiagramSettings(**kw)
    assert e.value.symbol == symbol
    if symbol == "df" and kw.get("stop") == 1e6:
        assert str(MAX_GRID_POINTS) in e.value.allowed


def test_orbit_diagram_in_pa_is_the_attractors_at_each_level():
    """--vary pa, a search at every point: at each P_a of the grid the diagram holds each of the
    search's periodic orbits once, as its k points (strobe points to 1e-6 µm)."""
    model = ContactModel()
    st = OrbitDiagramSettings(vary="pa", start=0.6, stop=0.65, step=0.05, n_periods=16, search_every=1,
                              n_starts=64)
    ds = orbit_diagram(model, fe_hz=360.0, settings=st)
    assert ds.attrs["vary"] == "pa" and np.all(ds["fe_hz"].values == 360.0)
    for pa in (0.6, 0.65):
        sel = np.isclose(ds["pa_over_q"].values, pa)
        ys, periods = ds["y_um"].values[sel], ds["period"].values[sel]
        found = find_attractors(Excitation(model, pa, 360.0), n_starts=64)
        assert ys.size == sum(a.period for a in found)  # each orbit once, as its k points
        for att in found:
            for y in att.strobe_y_um:
                j = np.argmin(np.abs(ys - y))
                assert abs(ys[j] - y) < 1e-6 and periods[j] == att.period


@pytest.mark.slow  # two spawned processes: ~15 s on 2 shared cores
def test_orbit_diagram_in_two_processes_equals_one():
    """Two worker processes (parts 358–360 and 360–361 Hz, a search at every point) give the same
    points (1e-6 µm) and periods as one process, each attractor with one id per point."""
    from contactvib.steady.diagram_pool import split_grid

    assert split_grid(4, 2) == [(0, 2), (2, 3)] and split_grid(121, 2) == [(0, 60), (60, 120)]
    st = OrbitDiagramSettings(start=358.0, stop=361.0, step=1.0, n_periods=8, search_every=1, n_starts=64)
    one = orbit_diagram(ContactModel(), pa_over_q=0.65, settings=st)
    two = orbit_diagram(ContactModel(), pa_over_q=0.65, settings=st, workers=2)

    def points(ds):
        return np.array(sorted(zip(ds["grid_index"].values, ds["period"].values, ds["y_um"].values)))

    a, b = points(one), points(two)
    assert a.shape == b.shape
    np.testing.assert_array_equal(a[:, :2], b[:, :2])
    np.testing.assert_allclose(a[:, 2], b[:, 2], rtol=0, atol=1e-6)
    for ds in (one, two):
        pairs = list(zip(ds["grid_index"].values.tolist(), ds["attractor"].values.tolist(), ds["k"].values.tolist()))
        assert len(pairs) == len(set(pairs))


def test_a_long_period_orbit_is_found_periodic_by_the_search_and_its_section():
    """0.9 Q, 1300 Hz: an attractor whose period exceeds the search's kmax (8) was once called
    chaotic; the search's verdict (the Lyapunov spectrum, then the orbit in the strobe sequence)
    lists it as a stable period-12 orbit, and its section is its 12 points (λ1 < 0). Independent
    check: scipy (rtol 1e-12, located switches) returns to the first point after 12 periods (1e-6)."""
    exc = Excitation(ContactModel(), 0.9, 1300.0)
    found = find_attractors(exc, n_starts=512)
    assert not [a for a in found if a.kind == "chaotic"]
    twelve = [i for i, a in enumerate(found) if a.period == 12]
    assert twelve
    s = poincare_sections(exc, found, n_periods=400)[twelve[0]]
    assert s.period == 12 and s.kind == "periodic"
    assert s.y_um.size == 12 and s.lambda1 < 0
    u = exc.model.units
    z0 = np.array(u.state(s.y_um[0], s.ydot_mm_s[0]))
    fc, ff = power_law_rhs(exc.kernel_parameters())
    tr = integrate_modes(fc, ff, z0, 0.0, 12 * exc.tau_period, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(tr.y, z0, rtol=0, atol=1e-6)
