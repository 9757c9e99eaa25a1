"""Issue 14, Acceptance, at full size (slow, opt-in: ``pytest -m slow``): the atlas at the
paper's eight levels, 30–2000 Hz at 1 Hz, equals ``contactvib paper``'s dataset (same attractors,
values to 1e-10 relative), the atlas on a Dask LocalCluster and the paper on the local pool.
The default suite checks the same on a reduced grid (test_atlas_equals_paper.py)."""

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from contactvib.sweeps.paper import PAPER_LEVELS


@pytest.mark.slow
def test_atlas_at_the_papers_levels_equals_paper_at_1_hz(tmp_path):
    assert main(["paper", "--no-progress", "--workers", "2", "--out", str(tmp_path / "paper")]) == 0
    levels = [f"{p:g}" for p in PAPER_LEVELS]
    assert main(["atlas", "--pa", *levels, "--fmin", "30", "--fmax", "2000", "--df", "1", "--no-progress",
                 "--dask-workers", "2", "--out", str(tmp_path / "atlas")]) == 0
    paper = xr.load_dataset(tmp_path / "paper" / "paper.nc")
    atlas = xr.load_dataset(tmp_path / "atlas" / "atlas.nc")
    assert paper.sizes["point"] > 60_000  # the full grid, not a reduced one
    assert dict(atlas.sizes) == dict(paper.sizes) and set(atlas.variables) == set(paper.variables)
    for name, var in paper.variables.items():
        if var.dtype.kind == "f":
            np.testing.assert_allclose(atlas[name].values, var.values, rtol=1e-10, atol=0, equal_nan=True,
                                       err_msg=name)
        else:  # same attractors: levels, frequencies, kinds, labels, branches, origins
            np.testing.assert_array_equal(atlas[name].values, var.values, err_msg=name)
