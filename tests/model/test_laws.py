"""Contact-law families and excitations: closed forms of the derived scales, the compiled spring
forces against their formulas, and the refusal of bad input.

Closed forms (W = Q + F_pre the static load, k the linear stiffness at y0):

* power law with preload: y0 = (W/(S c_n))^(1/m2), f_n0 = sqrt(m2 W/(y0 M))/2π (rel 1e-13);
* exponential law: y0 = λ ln(1 + W/(S c_e)), k = (W + S c_e)/λ (rel 1e-13);
* table law: a linear table F = k y is interpolated exactly by PCHIP (y0 = W/k, k_lin = k, rel
  1e-13); a table sampled from the power law gives its y0 (rel 1e-6 with 400 rows, 1e-7 with
  2000) and f_n0 (PCHIP's slopes are first order in the row spacing: rel 2e-4 with 400 rows,
  1e-5 with 2000);
* Hunt–Crossley damping: c_lin = α W, ζ = α W/(2 sqrt(k M)) (rel 1e-13) with every spring.
"""

import json
import math

import numpy as np
import pytest

from contactvib import ContactModel, Excitation, ParameterError
from contactvib.model.laws import ExponentialLaw, TableLaw

PAPER = ContactModel()
Q = PAPER.M * PAPER.g


def _power_table(n, y_max=4e-6, m2=2.0):
    return TableLaw.from_function(lambda y: PAPER.S * PAPER.c_n * y**m2, y_max, n)


# ------------------------------------------------------------------------------ closed forms
@pytest.mark.parametrize("preload", [0.0, 0.5, 2.0, 20.0])
@pytest.mark.parametrize("m2, c_n", [(2.0, 4.52e16), (1.5, 1e13), (3.0, 1e23)])
def test_preloaded_power_law_closed_forms(preload, m2, c_n):
    m = ContactModel(m2=m2, c_n=c_n, preload=preload)
    W = Q + preload
    y0 = (W / (m.S * c_n)) ** (1.0 / m2)
    assert m.W == pytest.approx(W, rel=1e-15)
    assert m.y0 == pytest.approx(y0, rel=1e-13)
    assert m.k_lin == pytest.approx(m2 * W / y0, rel=1e-13)
    assert m.f_n0 == pytest.approx(math.sqrt(m2 * W / (y0 * m.M)) / (2.0 * math.pi), rel=1e-13)
    assert m.zeta == pytest.approx(m.S * m.h_n * y0**m.l / (2.0 * math.sqrt(m2 * W / y0 * m.M)), rel=1e-13)
    assert float(m.spring_force(y0)) == pytest.approx(-W, rel=1e-13)


@pytest.mark.parametrize("c_e, lam", [(None, None), (584.0, 0.1413e-6), (50.0, 0.05e-6), (1e4, 0.5e-6)])
@pytest.mark.parametrize("preload", [0.0, 1.0])
def test_exponential_law_closed_forms(c_e, lam, preload):
    m = ContactModel(law="exponential", c_e=c_e, lam=lam, preload=preload)
    c_e = 584.0 if c_e is None else c_e
    lam = 0.1413e-6 if lam is None else lam
    W = Q + preload
    assert (m.c_e, m.lam) == (c_e, lam)
    assert m.y0 == pytest.approx(lam * math.log(1.0 + W / (m.S * c_e)), rel=1e-13)
    k = (W + m.S * c_e) / lam
    assert m.k_lin == pytest.approx(k, rel=1e-13)
    assert m.f_n0 == pytest.approx(math.sqrt(k / m.M) / (2.0 * math.pi), rel=1e-13)
    assert m.kappa == pytest.approx(k * m.y0 / W, rel=1e-13)
    assert m.zeta == pytest.approx(m.S * m.h_n * m.y0**m.l / (2.0 * math.sqrt(k * m.M)), rel=1e-13)


def test_exponential_law_object_and_defaults():
    """ContactModel(law=ExponentialLaw(...)) equals the named form; the defaults give the paper's
    y0 and f_n0 to 1 % (their documented purpose)."""
    a = ContactModel(law=ExponentialLaw(100.0, 0.2e-6))
    b = ContactModel(law="exponential", c_e=100.0, lam=0.2e-6)
    assert a == b and a.y0 == b.y0
    d = ContactModel(law="exponential")
    assert d.y0 == pytest.approx(PAPER.y0, rel=0.01)
    assert d.f_n0 == pytest.approx(PAPER.f_n0, rel=0.01)


@pytest.mark.parametrize("law", ["power", "exponential", "table"])
@pytest.mark.parametrize("alpha, preload", [(None, 0.0), (10.0, 0.0), (60.0, 3.0)])
def test_hunt_crossley_zeta_closed_form(law, alpha, preload):
    table = _power_table(400) if law == "table" else None
    m = ContactModel(law=law, table=table, damping="hunt-crossley", alpha=alpha, preload=preload)
    alpha = 34.4 if alpha is None else alpha
    W = Q + preload
    assert m.alpha == alpha
    assert m.c_lin == pytest.approx(alpha * W, rel=1e-14)
    assert m.zeta == pytest.approx(alpha * W / (2.0 * math.sqrt(m.k_lin * m.M)), rel=1e-13)
    assert m.damping_coefficient == pytest.approx(alpha * m.y0 * m.omega_n0, rel=1e-13)


def test_hunt_crossley_default_matches_the_paper_damping_ratio():
    assert ContactModel(damping="hunt-crossley").zeta == pytest.approx(PAPER.zeta, rel=0.01)


def test_linear_table_is_exact():
    """PCHIP reproduces a straight line: y0 = W/k and k_lin = k (rel 1e-13), any row spacing."""
    k = 1.2e7
    d = np.array([0.0, 0.05e-6, 0.1e-6, 0.4e-6, 0.45e-6, 1e-6])
    for preload in (0.0, 1.5):
        m = ContactModel(law=TableLaw(d, k * d), preload=preload)
        W = Q + preload
        assert m.y0 == pytest.approx(W / k, rel=1e-13)
        assert m.k_lin == pytest.approx(k, rel=1e-13)
        assert m.f_n0 == pytest.approx(math.sqrt(k / m.M) / (2.0 * math.pi), rel=1e-13)


@pytest.mark.parametrize("n, rel_y0, rel_f", [(400, 1e-6, 2e-4), (2000, 1e-7, 1e-5)])
@pytest.mark.parametrize("preload", [0.0, 1.0])
def test_table_sampled_from_the_power_law(n, rel_y0, rel_f, preload):
    p = ContactModel(preload=preload)
    t = ContactModel(law=_power_table(n), preload=preload)
    assert t.y0 == pytest.approx(p.y0, rel=rel_y0)
    assert t.f_n0 == pytest.approx(p.f_n0, rel=rel_f)
    assert t.zeta == pytest.approx(p.zeta, rel=rel_f)


# ------------------------------------------------------------------------------ spring forces
def test_compiled_spring_forces_match_the_formulas():
    """model.spring_force (the compiled law, through the kernels' nondimensional form) against
    the SI formulas; the table against scipy's PCHIP inside and the last slope beyond (rel 1e-12),
    and 0 in flight."""
    from scipy.interpolate import PchipInterpolator

    y = np.array([-0.3e-6, 0.0, 1e-9, 0.1e-6, 0.2254e-6, 0.7e-6, 2.0e-6, 3.9e-6])
    pos = np.maximum(y, 0.0)
    pre = ContactModel(m2=1.5, c_n=1e13, preload=0.7)
    expo = ContactModel(law="exponential", preload=0.7)
    table = _power_table(300, y_max=2.5e-6)
    tab = ContactModel(law=table)
    pchip = PchipInterpolator(table.deflection_m, table.load_n)
    slope = float(pchip.derivative()(table.y_max))
    F_tab = np.where(pos <= table.y_max, pchip(np.minimum(pos, table.y_max)),
                     table.load_n[-1] + slope * (pos - table.y_max))
    for m, F in ((pre, pre.S * pre.c_n * pos**1.5),
                 (expo, expo.S * expo.c_e * np.expm1(pos / expo.lam)),
                 (tab, F_tab)):
        got = -m.spring_force(y)
        assert np.all(got[y <= 0.0] == 0.0)
        assert np.allclose(got, np.where(y > 0.0, F, 0.0), rtol=1e-12, atol=0.0)
        assert np.allclose(m.conservative_force(y), m.W + m.spring_force(y), rtol=1e-15)


def test_table_from_csv_equals_the_arrays(tmp_path):
    """The CSV reader (µm, N; header in any column order, blank lines, spaces) gives the table of
    the same rows in metres."""
    d_um = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 2.0])
    F = np.array([0.0, 0.3, 1.5, 5.0, 17.0, 60.0])
    text = "load_n, deflection_um\n\n" + "".join(f"{b!r}, {a!r}\n" for a, b in zip(d_um.tolist(), F.tolist()))
    (tmp_path / "t.csv").write_text(text)
    t = TableLaw.from_csv(tmp_path / "t.csv")
    assert np.array_equal(t.deflection_m, d_um * 1e-6) and np.array_equal(t.load_n, F)
    assert t == TableLaw(d_um * 1e-6, F)
    assert ContactModel(law=t).y0 == ContactModel(law="table", table=TableLaw(d_um * 1e-6, F)).y0


def test_table_model_parameters_round_trip():
    m = ContactModel(law=_power_table(1000))
    again = ContactModel(**json.loads(json.dumps(m.parameters())))
    assert again == m and again.parameters() == m.parameters()


@pytest.mark.parametrize("kw", [dict(preload=1.0), dict(law="exponential", c_e=200.0, lam=0.1e-6),
                                dict(damping="hunt-crossley", alpha=20.0, preload=0.3),
                                dict(law="exponential", damping="hunt-crossley")])
def test_model_parameters_round_trip(kw):
    m = ContactModel(**kw)
    again = ContactModel(**json.loads(json.dumps(m.parameters())))
    assert again == m and again.parameters() == m.parameters() and again.y0 == m.y0


# ------------------------------------------------------------------------------ excitations
def test_excitation_levels():
    """Force, harmonics, base U and base A: the equivalent force amplitude at f_e over Q."""
    m = ContactModel(preload=1.0)
    f = 1000.0
    w = 2.0 * math.pi * f
    h = m.excitation(0.2, f, harmonics=((2, 0.1, 30.0), (3.0, 0.05, -45)))
    assert h.kind == "harmonics" and h.harmonics == ((2, 0.1, 30.0), (3, 0.05, -45.0))
    assert h.pa_over_q == 0.2 and h.P_a == pytest.approx(0.2 * Q, rel=1e-15)
    u = Excitation.base(m, f, u_um=0.05)
    assert u.kind == "base" and u.level == ("U", 0.05, "um")
    assert u.pa_over_q == pytest.approx(m.M * 0.05e-6 * w * w / Q, rel=1e-14)
    a = Excitation.base(m, f, a_g=0.3)
    assert a.level == ("A", 0.3, "g")
    assert a.P_a == pytest.approx(m.M * 0.3 * 9.80665, rel=1e-14)


# ------------------------------------------------------------------------------ bad input
def _raises(symbol, match, fn, *args, **kw):
    with pytest.raises(ParameterError, match=match or None) as e:
        fn(*args, **kw)
    assert e.value.symbol == symbol
    return e.value


D4 = np.array([0.0, 0.1e-6, 0.2e-6, 0.4e-6])
F4 = np.array([0.0, 1.0, 3.0, 9.0])


@pytest.mark.parametrize("d, F, match", [
    (D4, np.array([0.0, 1.0, 1.0, 9.0]), "load must increase strictly; rows 2 and 3"),
    (D4, np.array([0.0, 3.0, 1.0, 9.0]), "load must increase strictly"),
    (np.array([0.0, 0.2e-6, 0.1e-6, 0.4e-6]), F4, "deflection must increase strictly"),
    (D4 + 0.05e-6, F4, r"must start at \(0, 0\)"),
    (D4, F4 + 0.5, r"must start at \(0, 0\)"),
    (np.array([0.0, 0.1e-6, np.nan, 0.4e-6]), F4, "row 3 is not a finite number"),
    (D4, np.array([0.0, 1.0, 3.0, np.inf]), "row 4 is not a finite number"),
    (D4[:3], F4[:3], "has 3 rows: needs at least 4"),
    (D4, F4[:3], "same length"),
])
def test_bad_table_arrays(d, F, match):
    _raises("law_file", match, TableLaw, d, F)


@pytest.mark.parametrize("text, match", [
    ("deflection_um,load\n0,0\n0.1,1\n0.2,3\n0.4,9\n", "has no column load_n"),
    ("load_n\n0\n1\n3\n9\n", "has no column deflection_um"),
    ("", "is empty"),
    ("deflection_um,load_n\n0,0\n0.1,1\n0.2,x\n0.4,9\n", "line 4 is not two numbers"),
    ("deflection_um,load_n\n0,0\n0.1,1\n0.2\n0.4,9\n", "line 4 is not two numbers"),
    ("deflection_um,load_n\n0,0\n0.1,1\n0.3,3\n0.2,9\n", "deflection must increase strictly"),
    ("deflection_um,load_n\n0.01,0\n0.1,1\n0.2,3\n0.4,9\n", r"must start at \(0, 0\)"),
    ("deflection_um,load_n\n0,0\n0.1,1\n0.2,3\n", "has 3 rows"),
    ("deflection_um,load_n\n0,0\n0.1,1\nnan,3\n0.4,9\n", "row 3 is not a finite number"),
])
def test_bad_table_files(tmp_path, text, match):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    err = _raises("law_file", match, TableLaw.from_csv, p)
    assert "bad.csv" in str(err)


def test_missing_table_file(tmp_path):
    _raises("law_file", "cannot be read", TableLaw.from_csv, tmp_path / "absent.csv")


def test_table_that_does_not_reach_the_static_load_is_refused():
    """Largest load below W: refused (ParameterError naming the table); with a preload the same
    table that carries Q alone is refused too."""
    short = TableLaw(D4, np.array([0.0, 0.5, 1.0, 1.5]))  # 1.5 N < Q = 2.07 N
    with pytest.raises(ParameterError):
        ContactModel(law=short)
    enough = TableLaw(D4, np.array([0.0, 0.5, 1.0, 2.5]))
    ContactModel(law=enough)
    with pytest.raises(ParameterError):
        ContactModel(law=enough, preload=1.0)


def test_table_that_does_not_reach_the_static_load_says_so():
    short = TableLaw(D4, np.array([0.0, 0.5, 1.0, 1.5]))
    _raises("law_file", "does not reach the static load", ContactModel, law=short)


@pytest.mark.parametrize("kw, symbol, match", [
    (dict(law="exponential", lam=-1e-7), "lam", "must be > 0"),
    (dict(law="exponential", lam=0.0), "lam", "must be > 0"),
    (dict(law="exponential", c_e=-5.0), "c_e", "must be > 0"),
    (dict(law="exponential", c_e=math.nan), "c_e", ""),
    (dict(c_e=584.0), "c_e", "parameter of the exponential law"),
    (dict(law="power", lam=1e-7), "lam", "parameter of the exponential law"),
    (dict(alpha=30.0), "alpha", "Hunt-Crossley"),
    (dict(damping="power", alpha=30.0), "alpha", "Hunt-Crossley"),
    (dict(damping="hunt-crossley", alpha=-1.0), "alpha", ""),
    (dict(law="hertz"), "law", "unknown law; known: power, exponential, table, clearance"),
    (dict(damping="viscous"), "damping", "must be one of power, hunt-crossley"),
    (dict(law="table"), "law_file", "needs a table"),
    (dict(law="power", table=TableLaw(D4, F4)), "law_file", "belongs to the table law"),
    (dict(preload=-0.1), "F_pre", ""),
])
def test_bad_law_parameters(kw, symbol, match):
    _raises(symbol, match, ContactModel, **kw)


def test_bad_exponential_law_object():
    _raises("lam", "must be > 0", ExponentialLaw, 584.0, -1e-7)
    _raises("c_e", "must be > 0", ExponentialLaw, 0.0, 1e-7)


@pytest.mark.parametrize("harmonics, symbol, match", [
    (((1.5, 0.1, 0.0),), "k", r"must be in \[2, 64\]"),
    (((2.5, 0.1, 0.0),), "k", "must be an integer"),
    (((1, 0.1, 0.0),), "k", r"must be in \[2, 64\]"),
    (((65, 0.1, 0.0),), "k", r"must be in \[2, 64\]"),
    (((0, 0.1, 0.0),), "k", ""),
    (((2, -0.1, 0.0),), "P_k/Q", ""),
    (((2, 0.1, 400.0),), "phase", ""),
    (((2, 0.1),), "harmonics", r"\(k, P_k/Q, phase_deg\)"),
    (3, "harmonics", "must be a sequence"),
])
def test_bad_harmonics(harmonics, symbol, match):
    _raises(symbol, match, PAPER.excitation, 0.2, 1000.0, harmonics=harmonics)


def test_bad_base_motion():
    _raises("base", "exactly one", Excitation.base, PAPER, 1000.0, u_um=0.05, a_g=0.3)
    _raises("base", "exactly one", Excitation.base, PAPER, 1000.0)
    _raises("base", "not both", Excitation, PAPER, 0.0, 1000.0, base_um=0.05, base_g=0.3)
    _raises("U", "", Excitation.base, PAPER, 1000.0, u_um=-0.05)
    _raises("A", "", Excitation.base, PAPER, 1000.0, a_g=-0.3)
    _raises("harmonics", "not to base motion", Excitation, PAPER, 0.0, 1000.0, harmonics=((2, 0.1, 0.0),),
            base_um=0.05)
