"""The law registry and its contract: every registered law against its own SI definition, the
compiled forms against the laws, the registration checks, and a law from another installed
package (entry-point group ``contactvib.laws``) offered by the command line and the explorer."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib._kernels import contact as kc
from contactvib.model import ParameterError
from contactvib.model.laws import (
    LawParameter,
    SpringLaw,
    TableLaw,
    contract,
    law_class,
    law_names,
    law_parameter_names,
    register_law,
    registry,
)

SRC = Path(__file__).resolve().parents[2] / "src"


def _model(name: str) -> ContactModel:
    if name == "table":
        d = np.linspace(0.0, 2e-6, 200)
        return ContactModel(law="table", table=TableLaw(d, 0.0009 * 4.52e16 * d**2))
    return ContactModel(law=name)


def test_compiled_codes_are_the_kernels():
    assert (contract.COMPILED_POWER, contract.COMPILED_EXPONENTIAL, contract.COMPILED_TABLE) == \
        (kc.SPRING_POWER, kc.SPRING_EXPONENTIAL, kc.SPRING_TABLE)


def test_builtin_laws_in_order_with_their_parameters():
    assert law_names()[:4] == ("power", "exponential", "table", "clearance")
    assert law_parameter_names()["clearance"] == ("c_lin", "gap_um")
    assert law_parameter_names()["exponential"] == ("c_e", "lam")
    with pytest.raises(ParameterError, match="unknown law; known: power, exponential, table, clearance"):
        law_class("hertz")


@pytest.mark.parametrize("name", ["power", "exponential", "table", "clearance"])
def test_every_law_fulfils_the_contract(name):
    m = _model(name)
    law = m.spring_law
    assert law.name == name
    # the static point: F_s(δ0) = W
    assert float(law.force(m.y0, m.S)) == pytest.approx(m.W, rel=1e-10)
    # the stiffness is the force's derivative (central differences, away from the kinks)
    d = m.y0 * np.array([0.3, 1.0, 2.5])
    h = 1e-6 * m.y0
    fd = (law.force(d + h, m.S) - law.force(d - h, m.S)) / (2 * h)
    np.testing.assert_allclose(law.stiffness(d, m.S), fd, rtol=1e-6)
    # nothing acts in flight
    assert np.all(law.force(-d, m.S) == 0.0) and np.all(law.stiffness(-d, m.S) == 0.0)
    # the compiled form (ContactModel.spring_force, the kernels' law) is the law's SI force
    y = law.engagement_m + m.y0 * np.array([0.1, 0.5, 1.0, 1.7, 3.0])
    np.testing.assert_allclose(-m.spring_force(y), law.force(y - law.engagement_m, m.S), rtol=1e-12)
    assert m.kappa == pytest.approx(m.k_lin * m.y0 / m.W, rel=1e-14)


PLUGIN = '''
import numpy as np
from contactvib.model.laws import LawParameter, SpringLaw


class CubicLaw(SpringLaw):
    """F_s = S (k1 d + k3 d^3)."""

    name = "demo-cubic"
    formula = "S (k1 y + k3 y^3) (a hardening spring)"
    parameters = (LawParameter("k1", "N/m^3", 1.0e10, "linear part"),
                  LawParameter("k3", "N/m^5", 1.0e22, "cubic part", 0.0, True))

    def force(self, delta, S):
        d = np.asarray(delta, float)
        return np.where(d > 0.0, S * (self.k1 * d + self.k3 * d ** 3), 0.0)

    def stiffness(self, delta, S):
        d = np.asarray(delta, float)
        return np.where(d > 0.0, S * (self.k1 + 3.0 * self.k3 * d ** 2), 0.0)
'''


def _plugin_law():
    """The plug-in's law class, from its source (the same code the installed package holds)."""
    namespace: dict = {}
    exec(PLUGIN, namespace)
    return namespace["CubicLaw"]


class _Hardening(_plugin_law()):
    """F_s = S (k1 δ + k3 δ³) registered under another name: a law that maps onto no compiled
    family (its tabulated form)."""

    name = "test-hardening"


@pytest.fixture
def hardening():
    register_law(_Hardening)
    yield _Hardening
    registry._laws.pop(_Hardening.name, None)


def test_tabulated_form_of_a_law_without_a_compiled_one(hardening):
    m = ContactModel(law="test-hardening", law_params={"k3": 3e22})
    law = m.spring_law
    assert law.values() == {"k1": 1e10, "k3": 3e22}
    d = m.y0 * np.geomspace(1e-3, 100.0, 500)
    # cubic Hermite with the law's own slopes on 801 geometric knots: a cubic force is exact
    F = law.force(d, m.S)
    np.testing.assert_allclose(-m.spring_force(d), F, rtol=1e-12, atol=1e-12 * m.W)
    with pytest.raises(ParameterError, match="beyond its tabulated form"):
        m.check_motion(2e4 * m.y0 * 1e6)


def test_registration_checks_the_declarations():
    class NoName(SpringLaw):
        name = "Bad Name"

    class Clash(SpringLaw):
        name = "clash"
        parameters = (LawParameter("M", "kg", 1.0, "taken by the model"),)

    class Other(SpringLaw):
        name = "clearance"

    for cls, match in ((NoName, "lower-case"), (Clash, "not one of"), (Other, "taken by")):
        with pytest.raises(TypeError, match=match):
            register_law(cls)
    with pytest.raises(TypeError, match="not a SpringLaw"):
        register_law(int)


def test_parameters_are_checked_against_their_bounds():
    cls = law_class("clearance")
    with pytest.raises(ParameterError, match=r"gap_um = 2e\+6: must be in \[0, 1e\+6\] um"):
        cls(gap_um=2e6)
    assert cls(1e10, 2.0).values() == {"c_lin": 1e10, "gap_um": 2.0}
    assert cls(1e10, 2.0) == cls(c_lin=1e10, gap_um=2.0) and hash(cls(1e10)) == hash(cls(c_lin=1e10))
    with pytest.raises(AttributeError):
        cls().c_lin = 3.0




def _install(site: Path, dist: str, module: str, code: str, entry: str) -> None:
    """Install a distribution as pip lays out a wheel: its package and its dist-info."""
    (site / module).mkdir(parents=True)
    (site / module / "__init__.py").write_text(textwrap.dedent(code))
    info = site / f"{dist}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {dist}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[contactvib.laws]\n{entry}\n")
    (info / "RECORD").write_text("")


def test_a_law_from_another_package_is_offered_everywhere(tmp_path):
    site = tmp_path / "site"
    _install(site, "contactvib_demo_law", "contactvib_demo_law", PLUGIN, "cubic = contactvib_demo_law:CubicLaw")
    _install(site, "contactvib_broken_law", "contactvib_broken_law", "", "broken = contactvib_broken_law:Missing")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(SRC)])}

    def run(*args, check=True):
        return subprocess.run([sys.executable, *args], capture_output=True, text=True, env=env, check=check)

    help_text = run("-m", "contactvib", "attractors", "--help").stdout
    assert "demo-cubic" in help_text and "hardening spring" in " ".join(help_text.split())
    r = run("-m", "contactvib", "attractors", "--law", "demo-cubic", "--set", "k3=2e22", "--pa", "0.3", "--fe",
            "1000", "--starts", "32", "--json")
    assert "contactvib_broken_law:Missing was not loaded" in r.stderr  # a broken plug-in only warns
    out = json.loads(r.stdout)
    assert out["model"]["law"] == "demo-cubic" and out["model"]["law_params"] == {"k1": 1e10, "k3": 2e22}
    assert out["attractors"] and all(a["period"] for a in out["attractors"])
    # the same model's static point from the plug-in's own force: f_n0 from k = F_s'(δ0)
    S, W = 0.0009, 0.2106 * 9.81
    d0 = float(np.roots([S * 2e22, 0.0, S * 1e10, -W]).real.max())
    assert out["fn0_hz"] == pytest.approx(math.sqrt(S * (1e10 + 6e22 * d0**2) / 0.2106) / (2 * math.pi), rel=1e-6)
    bad = run("-m", "contactvib", "attractors", "--law", "demo-cubic", "--set", "k1=-1", check=False)
    assert bad.returncode == 2 and bad.stderr.strip().splitlines()[-1] == \
        "contactvib: error: --set k1 (k1) = -1: must be > 0 N/m^3"
    # the explorer offers it: its chooser, its fields and the command line it writes
    page = run("-c", "from contactvib.explore.state import Point, MODEL_FIELDS; "
                     "p = Point.from_query({'law': 'demo-cubic', 'k3': '2e22'}); "
                     "print(p.law_choices(), 'k3' in MODEL_FIELDS, p.active(), p.model_args())").stdout
    assert "'demo-cubic'" in page and "True" in page and "('M', 'g', 'S', 'k1', 'k3', 'h_n', 'l')" in page
    assert "('--law', 'demo-cubic', '--set', 'k3=2e22')" in page
