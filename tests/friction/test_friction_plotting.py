"""The friction figures: what the axes hold (data, labels, scales)."""

import numpy as np

from contactvib import ContactModel, find_attractors
from contactvib.friction import FrictionModel, friction_at
from contactvib.friction.sweep import friction_vs_velocity
from contactvib.plotting.friction import friction_history_figure, friction_sweep_figure, plot_friction_sweep


def _point():
    m = ContactModel()
    exc = m.excitation(0.65, 360.0)
    return m, exc, list(find_attractors(exc, n_starts=16))


def test_sweep_axes_against_velocity():
    m, exc, found = _point()
    sweep = friction_vs_velocity(m, exc, found[3:], [0.01, 1.0, 100.0], FrictionModel())
    assert len(sweep) == 6 and sweep.to_dict()["points"][0]["vd_mm_s"] == 0.01
    ax = plot_friction_sweep(sweep, "vd_mm_s")
    curves = [line for line in ax.get_lines() if len(line.get_xdata()) == 3]
    assert len(curves) == 2 and ax.get_xscale() == "log"
    for line in curves:
        assert np.allclose(line.get_xdata(), [0.01, 1.0, 100.0])
        y = np.asarray(line.get_ydata())
        assert np.all(np.diff(y) > -1e-9) and abs(y[-1] - 1.0) < 1e-3  # a fast drive slips: ratio -> <R+>/W
    assert "v_d" in ax.get_xlabel() and "μ" in ax.get_ylabel()
    fig = friction_sweep_figure(sweep, "vd_mm_s")
    assert "P_a = 0.65 Q" in fig.axes[0].get_title()


def test_history_figure_has_the_three_panels():
    m, exc, found = _point()
    r = friction_at(exc, found[3])
    h = r.history(500)
    fig = friction_history_figure(h, r, "#3: ")
    axes = fig.axes
    assert len(axes) == 3
    assert [a.get_ylabel() for a in axes] == ["normal force [N]", "tangential force [N]", "slip velocity [mm/s]"]
    assert np.allclose(axes[0].get_lines()[0].get_ydata(), h.normal_force_n)
    assert "friction ratio 0.49" in axes[0].get_title()
