"""The explore page's continuation is the CLI's: the branch the page draws equals the branch
file that the command it prints (``contactvib continue … --no-switch``) writes, point by point."""

from __future__ import annotations

import shlex

import numpy as np
import xarray as xr

from contactvib.cli import main
from contactvib.cli.explore import _check, _continue, _find
from contactvib.explore.continuation_view import branch_figure, window_hz
from contactvib.explore.state import Point


def test_page_branch_equals_the_printed_command(tmp_path, capsys):
    point = Point()  # 0.65 Q, 360 Hz
    model, exc = _check(point)
    result = _find(model, exc)
    n = len(result) - 1  # the 1/4: in contact, smallest A_pp
    branch, command = _continue(point, model, exc, result, n)
    assert command.startswith("contactvib continue --pa 0.65 --from-fe 360 --attractor 4 --no-switch")
    assert window_hz(360.0) == (180.0, 720.0)
    argv = shlex.split(command)[1:] + ["--out", str(tmp_path / "cli")]
    assert main(argv) == 0
    capsys.readouterr()
    cli = xr.load_dataset(next((tmp_path / "cli").glob("branch_*_b0.nc")))
    assert cli.sizes["point"] == len(branch)
    for name in ("fe_hz", "app_um"):
        np.testing.assert_allclose(getattr(branch, name), cli[name].values, rtol=1e-9)
    assert np.array_equal(np.asarray(branch.stable, int), cli["stable"].values.astype(int))
    kinds = {s.type for s in branch.special}
    assert "fold" in kinds  # the 1/4 folds over at both ends of its bent peak
    fig = branch_figure(branch, 360.0, result[n].app_um)
    labels = {item.label["value"] for item in fig.legend[0].items}
    assert {"stable", "unstable", "fold", "selected attractor"} <= labels
