"""Reading and checking the measurement files of ``contactvib fit`` (:mod:`contactvib.fitting.data`):
every bad input is a ParameterError naming the data set, the row and what is wrong."""

import numpy as np
import pytest

from contactvib.fitting import decay_data, frf_data, read_decay, read_frf, read_static, static_data
from contactvib.model import ParameterError


def _write(tmp_path, text, name="d.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_static_file_is_read_with_comments_and_any_column_order(tmp_path):
    p = _write(tmp_path, "# a comment\ndeflection_um,load_n,extra\n0,0,x\n0.1,1,y\n0.2,3,z\n")
    d = read_static(p)
    assert np.allclose(d.load_n, [0, 1, 3]) and np.allclose(d.deflection_um, [0, 0.1, 0.2])


@pytest.mark.parametrize("text, words", [
    ("load,deflection_um\n1,1\n2,2\n3,3\n", "missing column load_n"),
    ("load_n,deflection_um\n1,1\n2,nan\n3,3\n", "line 3, column deflection_um"),
    ("load_n,deflection_um\n1,1\n-2,2\n3,3\n", "negative load"),
    ("load_n,deflection_um\n1,1\n2,2\n", "at least 3"),
    ("", "empty"),
])
def test_bad_static_files(tmp_path, text, words):
    with pytest.raises(ParameterError, match=words) as e:
        read_static(_write(tmp_path, text))
    assert e.value.symbol == "static"


def test_frf_sweeps_are_grouped_by_force_and_direction_in_file_order(tmp_path):
    rows = ["fe_hz,force_amplitude_n,app_um,direction"]
    rows += [f"{f},0.5,1,up" for f in (100, 110, 120)] + [f"{f},0.5,1,down" for f in (120, 110, 100)]
    rows += [f"{f},1.0,1,UP" for f in (100, 110, 120)]
    d = read_frf(_write(tmp_path, "\n".join(rows) + "\n"))
    assert [s.tolist() for s in d.sweeps] == [[0, 1, 2], [3, 4, 5], [6, 7, 8]]


@pytest.mark.parametrize("rows, words", [
    (["100,1,1,up", "90,1,1,up", "120,1,1,up"], "out of order"),
    (["100,1,1,up", "100,1,1,up", "120,1,1,up"], "duplicated"),
    (["120,1,1,down", "130,1,1,down", "100,1,1,down"], "strictly decreasing"),
    (["100,1,1,up", "110,1,1,sideways", "120,1,1,up"], "must be up or down"),
    (["100,1,1,up", "110,1,nan,up", "120,1,1,up"], "not a finite number"),
    (["100,1,1,up", "110,1,0,up", "120,1,1,up"], "app_um = 0: must be > 0"),
])
def test_bad_frf_files(tmp_path, rows, words):
    text = "fe_hz,force_amplitude_n,app_um,direction\n" + "\n".join(rows) + "\n"
    with pytest.raises(ParameterError, match=words):
        read_frf(_write(tmp_path, text))


def test_frf_misspelt_column(tmp_path):
    with pytest.raises(ParameterError, match="missing column force_amplitude_n"):
        read_frf(_write(tmp_path, "fe_hz,force_n,app_um,direction\n1,1,1,up\n2,1,1,up\n3,1,1,up\n"))


def test_decay_needs_a_few_cycles_and_increasing_times(tmp_path):
    t = np.linspace(0, 10, 200)
    ok = decay_data(t, np.cos(2 * np.pi * 0.5 * t) * np.exp(-0.1 * t))  # 5 cycles
    assert ok.n == 200 and ok.kind == "y_um"
    with pytest.raises(ParameterError, match="at least 3 cycles"):
        decay_data(t, np.cos(2 * np.pi * 0.1 * t))  # one cycle
    with pytest.raises(ParameterError, match="strictly increasing"):
        decay_data(t[::-1], np.cos(2 * np.pi * 0.5 * t))
    p = _write(tmp_path, "t_ms,a_ms2\n" + "\n".join(f"{a},{b}" for a, b in zip(t, np.sin(3 * t))) + "\n")
    assert read_decay(p).kind == "a_ms2"
    with pytest.raises(ParameterError, match="missing column y_um or a_ms2"):
        read_decay(_write(tmp_path, "t_ms,y\n1,1\n", "e.csv"))


def test_static_arrays_checked():
    with pytest.raises(ParameterError, match="negative load"):
        static_data([0, -1, 2], [0, 1, 2])
    with pytest.raises(ParameterError, match="direction 'left'"):
        frf_data([1, 2, 3], [1, 1, 1], [1, 1, 1], ["up", "up", "left"])


def test_decay_from_a_universal_file_dataset_58(tmp_path):
    """A time response written by pyuff as dataset 58 (displacement [m], time [s]) reads back as
    the same decay in µm and ms; a file with no dataset 58 is refused naming it."""
    import pyuff

    t = np.linspace(0.0, 5e-3, 400)
    y = 1e-7 * np.exp(-300 * t) * np.cos(2 * np.pi * 1500 * t)
    p = tmp_path / "tap.uff"
    uff = pyuff.UFF(str(p))
    uff.write_sets(pyuff.prepare_58(func_type=1, rsp_node=1, rsp_dir=3, ref_node=1, ref_dir=3, data=y, x=t,
                                    id1="tap test", rsp_ent_name="slider", ref_ent_name="slider",
                                    abscissa_spacing=1, abscissa_spec_data_type=17, ordinate_spec_data_type=8,
                                    orddenom_spec_data_type=13), mode="add")
    d = read_decay(p)
    assert d.kind == "y_um"
    np.testing.assert_allclose(d.t_ms, t * 1e3, rtol=1e-5, atol=2e-5)  # the UFF ASCII increment: 6 digits
    np.testing.assert_allclose(d.values, y * 1e6, rtol=1e-5, atol=1e-9)
    bad = tmp_path / "bad.uff"
    bad.write_text("not a universal file\n")
    with pytest.raises(ParameterError, match="decay"):
        read_decay(bad)
