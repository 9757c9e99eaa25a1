"""The explorer's Poincaré section of the selected attractor (explore/section_view.py): a
period-k orbit draws its k stroboscopic points, the same as the search's strobe points; a
non-periodic attractor its cloud; no selection, an empty figure."""

from __future__ import annotations

import numpy as np
from bokeh.models import GlyphRenderer

from contactvib import ContactModel, find_attractors
from contactvib.explore.section_view import SECTION_PERIODS, attractor_sections, section_figure


def _points(fig):
    r = [g for g in fig.renderers if isinstance(g, GlyphRenderer)]
    return (np.asarray(r[0].data_source.data["x"]), np.asarray(r[0].data_source.data["y"])) if r else None


def test_periodic_sections_are_the_strobe_points():
    exc = ContactModel().excitation(0.65, 360.0)
    result = find_attractors(exc)
    sections = attractor_sections(exc, result)
    assert len(sections) == len(result) >= 2
    for a, s in zip(result, sections):
        x, y = _points(section_figure(s))
        assert x.size == a.period
        assert np.allclose(np.sort(x), np.sort(a.strobe_y_um), rtol=1e-6, atol=1e-9)
        assert f"period {a.period}, {a.period} points" in section_figure(s).title.text


def test_a_non_periodic_attractor_draws_its_cloud():
    exc = ContactModel().excitation(0.75, 816.5)
    result = find_attractors(exc)
    chaotic = [i for i, a in enumerate(result) if a.period is None]
    assert chaotic  # the small-basin chaotic attractor of the 1/2 window
    s = attractor_sections(exc, result)[chaotic[0]]
    x, _y = _points(section_figure(s))
    assert x.size == SECTION_PERIODS and np.unique(np.round(x, 6)).size > 100


def test_no_selection_is_an_empty_figure():
    fig = section_figure(None)
    assert _points(fig) is None and fig.title.text.startswith("Poincaré section")
