"""One way to read a stored resonance dataset's levels: :class:`contactvib.sweeps.stored.ResonanceData`
(its ``levels``, ``level(p)``, ``points(p)``, ``attractors_at``) with the one tolerance rule
``LEVEL_TOL`` / ``matching_level``. No other module of the package finds a level's points, or a
dataset's levels, by comparing ``pa_over_q`` by hand (a grep over the sources)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "contactvib"
#: The accessor's module: the only one that compares stored levels.
HOME = SRC / "sweeps" / "stored.py"

#: A hand-written level mask or level list: |pa_over_q - p| against a tolerance, isclose, rounding
#: or comparing the variable, the distinct levels by np.unique / set.
HAND_MADE = [
    re.compile(r"np\.(abs|isclose|round|unique)\([^\n]*pa_over_q"),
    re.compile(r"\babs\([^)\n]*pa_over_q[^)\n]*-"),
    re.compile(r"\babs\([^)\n]*-\s*[\w.]*pa_over_q"),
    re.compile(r"\[\"pa_over_q\"\]\.values[^\n]*(==|<=|>=|!=)"),
    re.compile(r"\bds\.pa_over_q\s*[-=<>]"),
    re.compile(r"(sorted|set)\((set\()?[\w.]*\[\"pa_over_q\"\]"),
]


def _hand_made(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines()
            if not line.lstrip().startswith("#") and any(p.search(line) for p in HAND_MADE)]


def test_the_patterns_find_the_masks_they_replaced():
    old = [
        'sel = np.nonzero(np.abs(ds["pa_over_q"].values - pa_over_q) <= 1e-6)[0]',
        'if abs(tf.pa_over_q - pa) > 1e-6:',
        'self._pa = np.round(self.ds["pa_over_q"].values.astype(float), 6)',
        'levels = sorted(set(ds["pa_over_q"].values.tolist()))',
        'stored = np.unique(ds["pa_over_q"].values)',
        'sel = np.nonzero(np.abs(ds["pa_over_q"].values - pa) <= 1e-9)[0]',
        'keep = abs(ds.pa_over_q - p) < 1e-6',
    ]
    assert _hand_made("\n".join(old)) == old
    assert _hand_made("d = curve.pa_over_q - pa_over_q\nfrac = (pa_over_q - lo) / (hi - lo)\n"
                      'datasets = sorted(datasets, key=lambda d: float(d["pa_over_q"].values[0]))') == []


@pytest.mark.parametrize("path", sorted(p for p in SRC.rglob("*.py") if p != HOME),
                         ids=lambda p: str(p.relative_to(SRC)))
def test_no_level_is_matched_by_hand(path):
    found = _hand_made(path.read_text())
    assert not found, (f"{path.relative_to(SRC)} compares pa_over_q by hand: {found}; use "
                       "contactvib.sweeps.stored.ResonanceData (levels, match, points, level) or matching_level")
