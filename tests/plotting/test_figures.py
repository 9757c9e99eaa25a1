"""Figures are checked by their content, through the axes the plotting functions return: the data
drawn, the labels and units, the scales; not by the size of a PNG."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.colors import to_rgba

from contactvib import ContactModel, SweepSettings, attractor_history, find_attractors
from contactvib.plotting import (
    attractor_figure,
    extrema_diagram,
    plot_branches,
    plot_phase_portrait,
    plot_time_history,
    resonance_graph,
)
from contactvib.plotting.figures import new_figure
from contactvib.plotting.paper import TimeRow, level_figures, time_figure


@pytest.fixture(scope="module")
def model():
    return ContactModel()


@pytest.fixture(scope="module")
def main_resonance(model):
    """The main resonance at 360 Hz, 0.65 Q (loses contact) and its history."""
    exc = model.excitation(0.65, 360.0)
    found = find_attractors(exc, n_starts=64)
    att = max((a for a in found if a.period == 1), key=lambda a: a.app_um)
    return att, attractor_history(exc, att)


@pytest.fixture(scope="module")
def level(model):
    """A small sweep at 0.65 Q, 300–420 Hz (four resonances coexist near 360 Hz)."""
    from contactvib import resonance_dataset

    st = SweepSettings(fmin_hz=300.0, fmax_hz=420.0, df_hz=4.0, multistart_per_octave=4.0)
    return resonance_dataset(model, levels=[0.65], settings=st, workers=1, progress=False)


def _axes():
    return new_figure()[1][0, 0]


def test_time_history_draws_the_samples_y0_and_the_gap(main_resonance):
    att, h = main_resonance
    ax = plot_time_history(h, _axes())
    line = ax.lines[0]
    np.testing.assert_array_equal(line.get_xdata(), h.t_ms)
    np.testing.assert_array_equal(line.get_ydata(), h.y_um)
    y0 = [ln for ln in ax.lines if ln.get_label() == "equilibrium $y_0$"]
    assert len(y0) == 1 and y0[0].get_ydata()[0] == pytest.approx(0.2254, abs=5e-5)
    assert ax.get_xlabel() == "t [ms]" and ax.get_ylabel() == "y [µm]"
    # the orbit loses contact: a shaded gap reaching down to y_min
    gap = [c for c in ax.collections if c.get_label() == "loss of contact"]
    assert len(gap) == 1
    assert gap[0].get_paths()[0].vertices[:, 1].min() == pytest.approx(h.y_um.min(), rel=1e-12)
    assert h.y_um.min() == pytest.approx(att.ymin_um, rel=1e-3)


def test_phase_portrait_draws_velocity_against_displacement(main_resonance):
    _att, h = main_resonance
    ax = plot_phase_portrait(h, _axes())
    np.testing.assert_array_equal(ax.lines[0].get_xdata(), h.y_um)
    np.testing.assert_array_equal(ax.lines[0].get_ydata(), h.ydot_mm_s)
    assert ax.get_xlabel() == "y [µm]" and ax.get_ylabel() == "dy/dt [mm/s]"


def test_attractor_figure_has_two_panels_and_a_title_with_the_orbit(main_resonance):
    att, h = main_resonance
    fig = attractor_figure(h, att)
    assert len(fig.axes) == 2
    title = fig._suptitle.get_text()
    assert "period 1" in title and "1 minimum" in title and f"{att.app_um:.4g}" in title


def test_resonance_graph_draws_every_branch_on_a_log_axis(level, model):
    ax = resonance_graph(level, 0.65, ax=_axes())
    assert ax.get_yscale() == "log"
    assert ax.get_xlabel() == "$f_e$ [Hz]" and ax.get_ylabel() == "$A_{pp}$ [µm]"
    drawn = np.concatenate([ln.get_ydata() for ln in ax.lines if len(ln.get_xdata())])
    # every stored periodic A_pp is on some line (branches split only at grid holes)
    periodic = level["kind"].values == "periodic"
    assert np.isin(level["app_um"].values[periodic], drawn).all()
    # the main resonance is black, the 1/2 coloured: at 360 Hz both are drawn
    colours = {to_rgba(ln.get_color()) for ln in ax.lines}
    assert to_rgba("k") in colours and len(colours) >= 4
    # f_n0/m marks (Eq. 2.6), those inside the level's f_e range (a narrow sweep keeps its axis)
    marks = [ln for ln in ax.lines if ln.get_label() == "$f_{n0}/m$ (Eq. 2.6)"][0]
    fe = level["fe_hz"].values
    inside = [f for f in model.f_n0 / np.arange(1, 7) if fe.min() <= f <= fe.max()]
    assert inside and len(inside) < 6  # the fixture's range holds some marks, not all
    np.testing.assert_allclose(marks.get_xdata(), inside, rtol=1e-12)
    assert ax.get_xlim()[1] < 2 * fe.max()  # the axis is the level's, not stretched to f_n0


def test_extrema_diagram_draws_every_extremum(level):
    ax = extrema_diagram(level, 0.65, ax=_axes())
    assert ax.get_yscale() == "symlog"
    n = sum(len(ln.get_xdata()) for ln in ax.lines if ln.get_marker() == ",")
    assert n == level.sizes["extremum"]
    ys = np.concatenate([ln.get_ydata() for ln in ax.lines if ln.get_marker() == ","])
    assert ys.min() == pytest.approx(level["ymin_um"].min()) and ys.max() == pytest.approx(
        level["ymax_um"].max())


def test_level_figures_name_the_papers_panels(level):
    graph, extrema = level_figures(level, 0.65, ref="c")
    assert graph.axes[0].get_title() == "Resonance graph, $P_a$ = 0.65 Q (cf. Fig. 2c)"
    assert extrema.axes[0].get_title() == "Local extrema of y(t), $P_a$ = 0.65 Q (cf. Fig. 3c)"


def test_time_figure_has_one_row_per_attractor(main_resonance):
    att, h = main_resonance
    fig = time_figure([TimeRow(h, "a"), TimeRow(h, "b", series=h, series_label="series")], "T")
    assert len(fig.axes) == 4
    assert [fig.axes[i].get_title(loc="left") for i in (0, 2)] == ["a", "b"]
    # the overlaid series is drawn dashed red in the second row only
    dashed = [ln for ax in fig.axes for ln in ax.lines if ln.get_linestyle() == "--"
              and to_rgba(ln.get_color()) == to_rgba("tab:red")]
    assert len(dashed) == 2


def _laid_out(fig):
    """Every axes' tight box (ticks, labels, title, legend) inside the figure and no two of them
    overlapping: fixed margins (``set_margins``) cut nothing off and crowd nothing."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    page = fig.bbox
    boxes = [ax.get_tightbbox(renderer) for ax in fig.axes]
    if fig._suptitle is not None:
        boxes.append(fig._suptitle.get_window_extent(renderer))
    for b in boxes:
        assert page.x0 - 1 <= b.x0 and b.x1 <= page.x1 + 1 and page.y0 - 1 <= b.y0 and b.y1 <= page.y1 + 1, (b, page)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            overlap_w = min(a.x1, b.x1) - max(a.x0, b.x0)
            overlap_h = min(a.y1, b.y1) - max(a.y0, b.y0)
            assert overlap_w <= 1 or overlap_h <= 1, (a, b)


def test_paper_figures_keep_everything_inside_their_fixed_margins(level, main_resonance):
    for fig in level_figures(level, 0.65, ref="c"):
        _laid_out(fig)
    att, h = main_resonance
    title = "main: period 1, 1 minimum, $A_{pp}$ = 11.44 µm; perturbation not applicable (contact is lost)"
    for n in (1, 3):
        _laid_out(time_figure([TimeRow(h, title, series=h, series_label="perturbation, N = 80")] * n,
                              "cf. Fig. 4: $P_a$ = 0.65 Q, $f_e$ = 360 Hz (all attractors stored in the dataset)"))


def test_branches_stable_solid_unstable_dashed(model):
    from contactvib import continue_orbit
    from contactvib.continuation.shooting import ContinuationSettings

    exc = model.excitation(0.65, 1100.0)
    att = [a for a in find_attractors(exc, n_starts=32) if a.period == 1][0]
    b = continue_orbit(exc, att.state, 1, direction="down",
                       settings=ContinuationSettings(fmin_hz=900.0, fmax_hz=1100.0, max_points=80))
    ax = plot_branches([b], _axes())
    styles = {ln.get_linestyle() for ln in ax.lines if len(ln.get_xdata()) > 1}
    stable = np.asarray(b.stable)
    assert ("-" in styles) == bool(stable.any()) and ("--" in styles) == bool((~stable).any())
    assert ax.get_yscale() == "log"
    assert ax.get_ylabel() == "peak-to-peak amplitude $A_{pp}$ [µm]"
