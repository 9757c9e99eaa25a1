"""Every figure of contactvib (matplotlib is imported only in this package; every function takes
``ax=None``)."""

from contactvib.plotting.basins import basins_figure, plot_basins
from contactvib.plotting.branches import plot_branches, plot_evolution
from contactvib.plotting.figures import (
                                         attractor_figure,
                                         extrema_diagram,
                                         plot_phase_portrait,
                                         plot_time_history,
                                         resonance_graph,
)
from contactvib.plotting.frequency import overlay_figure, plot_branch, plot_convergence
from contactvib.plotting.sections import (
                                          orbit_diagram_figure,
                                          plot_impact_map,
                                          plot_orbit_diagram,
                                          plot_section,
                                          section_figure,
)

__all__ = ["plot_time_history", "plot_phase_portrait", "attractor_figure", "resonance_graph",
           "extrema_diagram", "plot_branches", "plot_evolution", "overlay_figure",
           "plot_convergence", "plot_branch", "plot_basins", "basins_figure", "plot_section", "plot_impact_map",
           "section_figure", "plot_orbit_diagram", "orbit_diagram_figure"]
