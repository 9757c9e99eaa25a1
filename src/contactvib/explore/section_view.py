"""The Poincaré section of the selected attractor in ``contactvib explore`` (a Bokeh figure),
from :func:`contactvib.steady.sections.attractor_section`."""

from __future__ import annotations

from bokeh.plotting import figure

__all__ = ["SECTION_PERIODS", "section_figure", "attractor_sections"]

#: Excitation periods of a non-periodic attractor's section in the page (a periodic one: its k).
SECTION_PERIODS = 400


def section_figure(section=None):
    """The stroboscopic Poincaré section (y, ẏ at t = k/f_e) of the selected attractor: its k
    points for a period-k orbit, its cloud or closed curve over :data:`SECTION_PERIODS` periods
    otherwise (:func:`contactvib.steady.sections.attractor_section`)."""
    title = "Poincaré section (t = k/f_e)"
    if section is not None:
        n = section.y_um.size
        title += (f": period {section.period}, {n} points" if section.period is not None
                  else f": {section.kind}, {n} points over {section.n_periods} periods")
    sec = figure(height=300, width=400, title=title, x_axis_label="y [µm]", y_axis_label="ẏ [mm/s]")
    if section is not None:
        sec.scatter(section.y_um, section.ydot_mm_s, size=5 if section.period is not None else 2,
                    color="#1f4e79")
    return sec


def attractor_sections(exc, result):
    """The section of every attractor (None where it cannot be integrated)."""
    from contactvib.errors import ComputationError
    from contactvib.steady.sections import attractor_section

    out = []
    for i, a in enumerate(result):
        try:
            out.append(attractor_section(exc, a, i, n_periods=SECTION_PERIODS))
        except ComputationError:
            out.append(None)
    return out
