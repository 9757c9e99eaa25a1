"""The colours of contactvib's figures, in one place (the matplotlib figures and the explorer's
Bokeh page use the same ones). No matplotlib at import: :func:`label_colours` imports it when
called.

- resonance orders: :func:`order_colour` (main resonance black, m = 2, 3, … from
  :data:`ORDER_COLOURS`): resonance graphs, extrema diagrams, regime maps, the film, the
  explorer;
- periods of continued branches: :func:`branch_period_colour` (branch figures);
- periods of the normal attractor under a friction sweep: :func:`friction_period_colour`;
- basins: :func:`label_colours` for the attractors, :data:`NO_ATTRACTOR_COLOUR` for the starts
  that reached none.
"""

from __future__ import annotations

__all__ = ["ORDER_COLOURS", "order_colour", "BRANCH_PERIOD_COLOURS", "branch_period_colour",
           "FRICTION_PERIOD_COLOURS", "friction_period_colour", "NO_ATTRACTOR_COLOUR", "label_colours"]

#: Colours of resonance orders m = 2, 3, … in every figure (matplotlib's "tab10", cycled); the
#: main resonance (m = 1) is black. Hex text, so the browser page uses the same colours.
ORDER_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
                 "#7f7f7f", "#bcbd22", "#17becf")

#: Colours of branch periods k in the branch figures (other periods: :data:`_OTHER_BRANCH_PERIOD`).
BRANCH_PERIOD_COLOURS = {1: "k", 2: "tab:blue", 3: "tab:green", 4: "tab:purple", 6: "tab:olive", 8: "tab:cyan"}
_OTHER_BRANCH_PERIOD = "tab:brown"

#: Colours of the normal attractor's period k = 1..4 in friction sweeps (k > 4: ``"C4"``).
FRICTION_PERIOD_COLOURS = {1: "C0", 2: "C1", 3: "C2", 4: "C3"}
_OTHER_FRICTION_PERIOD = "C4"

#: Colour of the basin starts that reached no attractor (label −1).
NO_ATTRACTOR_COLOUR = "0.6"


def order_colour(m: int) -> str:
    """The colour of resonance order ``m`` (1: main, black)."""
    return "#000000" if m == 1 else ORDER_COLOURS[(m - 2) % len(ORDER_COLOURS)]


def branch_period_colour(k: int) -> str:
    """The colour of a continued branch of period ``k``."""
    return BRANCH_PERIOD_COLOURS.get(k, _OTHER_BRANCH_PERIOD)


def friction_period_colour(k: int) -> str:
    """The colour of a normal attractor of period ``k`` in a friction sweep."""
    return FRICTION_PERIOD_COLOURS.get(k, _OTHER_FRICTION_PERIOD)


def label_colours(n: int) -> list:
    """``n`` distinct colours for the basin labels 0..n−1 (tab10, then tab20)."""
    from matplotlib import colormaps

    cmap = colormaps["tab10" if n <= 10 else "tab20"]
    return [cmap(i % cmap.N) for i in range(n)]
