"""The TOML system files (``contactvib.model.load_system``): the example round trip, and each bad
file refused with the key that is wrong (as a library error, and through the CLI as one line,
exit 2)."""

from pathlib import Path

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.model import ParameterError
from contactvib.model.laws import ClearanceLaw
from contactvib.model.system_file import load_system

EXAMPLE = Path(__file__).parents[2] / "examples" / "two_dof_stop.toml"


def test_the_example_round_trip():
    s = load_system(EXAMPLE)
    assert s.coordinates == ("q1", "q2") and s.units == ("m", "m")
    assert s.M.tolist() == [[1.0, 0.0], [0.0, 1.0]] and s.K.tolist() == [[1.0, -1.0], [-1.0, 2.0]]
    assert s.C.tolist() == [[0.03, -0.03], [-0.03, 0.06]]
    assert s.f0.tolist() == [0.0, 0.0] and s.b.tolist() == [0.0, 1.0]
    (c,) = s.contacts
    assert c.name == "stop" and c.direction == (1.0, 0.0) and c.S == 1.0 and c.damping == "power" and c.h_n == 0.0
    assert isinstance(c.law, ClearanceLaw) and c.law.values() == {"c_lin": 100.0, "gap_um": 1e6}
    assert c.engagement == pytest.approx(1.0)
    # the stop: 100 N/m beyond q1 = 1 m
    assert c.force(0.5, 0.0) == pytest.approx(50.0) and c.force(-0.1, 0.0) == 0.0
    np.testing.assert_allclose(s.linear_modes(), [0.0983632, 0.2575181], rtol=1e-6)


BASE = EXAMPLE.read_text()

#: (replacement of a line of the example, or text appended; the key the error names)
BAD = {
    "mass shape": (("mass = [[1.0, 0.0], [0.0, 1.0]]", "mass = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]"), "system.mass"),
    "mass not symmetric": (("mass = [[1.0, 0.0], [0.0, 1.0]]", "mass = [[1.0, 0.5], [0.0, 1.0]]"), "system.mass"),
    "mass not definite": (("mass = [[1.0, 0.0], [0.0, 1.0]]", "mass = [[1.0, 0.0], [0.0, -1.0]]"), "system.mass"),
    "stiffness shape": (("stiffness = [[1.0, -1.0], [-1.0, 2.0]]", "stiffness = [1.0, 2.0]"), "system.stiffness"),
    "load NaN": (("static_load = [0.0, 0.0]", "static_load = [nan, 0.0]"), "system.static_load"),
    "missing force shape": (("force_shape = [0.0, 1.0]", ""), "system.force_shape"),
    "missing mass": (("mass = [[1.0, 0.0], [0.0, 1.0]]", ""), "system.mass"),
    "unknown system key": (("force_shape = [0.0, 1.0]", "force_shape = [0.0, 1.0]\nmasses = 1"), "system.masses"),
    "unknown law": (('law = "clearance"', 'law = "glue"'), "contact[0].law"),
    "unknown law parameter": (("c_lin = 100.0", "c_n = 100.0"), "contact[0].c_n"),
    "law parameter out of range": (("gap_um = 1.0e6", "gap_um = -1.0"), "contact[0].gap_um"),
    "zero direction": (("direction = [1.0, 0.0]", "direction = [0.0, 0.0]"), "contact[0].direction"),
    "direction shape": (("direction = [1.0, 0.0]", "direction = [1.0]"), "contact[0].direction"),
    "missing direction": (("direction = [1.0, 0.0]", ""), "contact[0].direction"),
    "negative area": (("area = 1.0", "area = -1.0"), "contact[0].area"),
    "unknown damping": (('law = "clearance"', 'law = "clearance"\ndamping = "viscous"'), "contact[0].damping"),
    "coordinates count": (('coordinates = ["q1", "q2"]', 'coordinates = ["q1"]'), "system.coordinates"),
    "not TOML": (("[system]", "[system"), "file"),
}


def _bad_file(tmp_path, case) -> Path:
    (old, new), _ = BAD[case]
    lines = [new if line.split("#")[0].strip() == old else line for line in BASE.splitlines()]
    assert lines != BASE.splitlines(), case
    path = tmp_path / "bad.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("case", BAD)
def test_a_bad_file_names_its_key(tmp_path, case):
    with pytest.raises(ParameterError) as e:
        load_system(_bad_file(tmp_path, case))
    assert e.value.symbol == BAD[case][1]


@pytest.mark.parametrize("case", ["mass not definite", "unknown law parameter", "zero direction",
                                  "missing force shape", "load NaN"])
def test_a_bad_file_is_one_line_exit_2(tmp_path, case, capsys):
    path = _bad_file(tmp_path, case)
    rc = main(["attractors", "--system", str(path), "--pa-newton", "1", "--fe", "0.2"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert err.startswith(f"contactvib: error: --system {path}: {BAD[case][1]}"), err


def test_pa_is_refused_for_a_file(capsys):
    rc = main(["attractors", "--system", str(EXAMPLE), "--pa", "0.5", "--fe", "0.2"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and "--pa-newton" in err, err
