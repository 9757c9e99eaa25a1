"""Issue 14, Acceptance: the atlas at the paper's eight levels equals ``contactvib paper``'s
dataset (same attractors, values to 1e-10 relative), on a reduced grid (300–400 Hz, 10 Hz, few
starts) in the default suite; the compressed store changes no value."""

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from contactvib.sweeps.paper import PAPER_LEVELS

GRID = ["--fmin", "300", "--fmax", "400", "--df", "10", "--multistart-per-octave", "2", "--starts", "4",
        "--no-progress", "--workers", "2"]


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper_vs_atlas")
    assert main(["paper", *GRID, "--out", str(out / "paper")]) == 0
    levels = [f"{p:g}" for p in PAPER_LEVELS]
    assert main(["atlas", "--pa", *levels, *GRID, "--out", str(out / "atlas")]) == 0
    return xr.load_dataset(out / "paper" / "paper.nc"), xr.load_dataset(out / "atlas" / "atlas.nc")


def test_same_attractors(both):
    paper, atlas = both
    assert len(PAPER_LEVELS) == 8
    assert dict(atlas.sizes) == dict(paper.sizes) and paper.sizes["point"] >= 8 * 11
    assert sorted(np.unique(atlas["pa_over_q"].values)) == sorted(PAPER_LEVELS)
    for name in ("pa_over_q", "fe_hz", "period", "kind", "attractor_type", "resonance", "origin", "found_by",
                 "minima_per_period"):
        np.testing.assert_array_equal(atlas[name].values, paper[name].values, err_msg=name)


def test_values_to_1e_10(both):
    paper, atlas = both
    assert set(atlas.variables) == set(paper.variables)
    for name, var in paper.variables.items():
        a = atlas[name].values
        if var.dtype.kind == "f":
            np.testing.assert_allclose(a, var.values, rtol=1e-10, atol=0, equal_nan=True, err_msg=name)
        else:
            np.testing.assert_array_equal(a, var.values, err_msg=name)
