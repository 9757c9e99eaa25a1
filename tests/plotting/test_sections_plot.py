"""The section, impact-map and orbit-diagram figures, checked through their axes: the points drawn
(a period-k orbit's k points), the labels with units, the λ1 colour bar."""

import numpy as np
import pytest

from contactvib import ContactModel, Excitation, find_attractors
from contactvib.plotting.sections import LAMBDA_LABEL, orbit_diagram_figure, section_figure
from contactvib.steady.orbit_diagram import OrbitDiagramSettings, orbit_diagram
from contactvib.steady.sections import poincare_sections
from figure_files import assert_figure_file


@pytest.fixture(scope="module")
def sections():
    exc = Excitation(ContactModel(), 0.65, 360.0)
    return poincare_sections(exc, find_attractors(exc, n_starts=64), n_periods=20)


def test_section_figure_draws_each_orbits_points(sections, tmp_path):
    fig = section_figure(sections, impacts=True)
    ax, ax_imp = fig.axes[:2]
    lines = [ln for ln in ax.get_lines() if ln.get_label().startswith("#")]
    assert len(lines) == len(sections)
    for ln, s in zip(lines, sections):
        np.testing.assert_array_equal(ln.get_xdata(), s.y_um)
        assert f"period {s.period}: {s.period} point" in ln.get_label()
    assert "[µm]" in ax.get_xlabel() and "[mm/s]" in ax.get_ylabel()
    assert "fraction of the period" in ax_imp.get_xlabel() and "[mm/s]" in ax_imp.get_ylabel()
    from contactvib.plotting.figures import save_figure

    assert_figure_file(save_figure(fig, tmp_path / "s.png"))


def test_orbit_diagram_figure_has_a_lambda1_colour_bar():
    ds = orbit_diagram(ContactModel(), pa_over_q=0.65,
                       settings=OrbitDiagramSettings(start=359.0, stop=360.0, step=1.0, n_periods=8, n_starts=32))
    fig = orbit_diagram_figure(ds)
    ax, cax = fig.axes[:2]
    assert cax.get_ylabel() == LAMBDA_LABEL == "λ1 [1/period]"
    assert "[Hz]" in ax.get_xlabel() and "[µm]" in ax.get_ylabel()
    offsets = ax.collections[0].get_offsets()
    assert offsets.shape[0] == ds.sizes["point"]
    fig2 = orbit_diagram_figure(ds, "v-loss")
    assert "contact loss [mm/s]" in fig2.axes[0].get_ylabel()
    assert fig2.axes[0].collections[0].get_offsets().shape[0] == ds.sizes["loss"]
