"""The multi-start kernel: its threaded and serial loops give the same starts' results, and a
pool worker (one numba thread) takes the serial one."""

from __future__ import annotations

import numba
import numpy as np

from contactvib._kernels import table as tb
from contactvib._kernels.status import SETTLE_CAPTURED, SETTLE_PERIODIC
from contactvib.model import ContactModel
from contactvib.steady.attractors import ballistic_seeds, start_box
from contactvib.sweeps.level_state import LevelState
from contactvib.sweeps.sweep import SweepSettings, _settle_from


def _level_with_known_orbit():
    """One grid frequency (0.65 Q, 360 Hz: five attractors) with the up-sweep's orbit traced."""
    model = ContactModel()
    st = SweepSettings(fmin_hz=360.0, fmax_hz=361.0, df_hz=1.0)
    lv = LevelState(model, 0.65, np.array([360.0, 361.0]), st)
    z, k, kind = _settle_from(lv, 0, (1.0, 0.0))
    lv.trace(z, k, kind, 0, +1, "up-sweep", "sweep")
    exc = model.excitation(0.65, 360.0)
    Zb, phb = start_box(exc, 24, 7)
    Zs, phs = ballistic_seeds(exc)
    par = lv.par.copy()
    par[4] = lv.r[0]
    return lv, np.vstack([Zb, Zs]), np.concatenate([phb, phs]), par


def test_threaded_and_serial_loops_agree_exactly():
    lv, Z, ph, par = _level_with_known_orbit()
    args = (Z, ph, 0, par, lv.cfg, lv.st.capture_tol, lv.table)
    a = tb._settle_known_threads(*args)
    b = tb._settle_known_serial(*args)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    status = a[0]
    assert (status == SETTLE_PERIODIC).any()  # new attractors settled
    assert (status == SETTLE_CAPTURED).any()  # and starts captured by the known orbit


def test_one_thread_takes_the_serial_loop(monkeypatch):
    lv, Z, ph, par = _level_with_known_orbit()
    used = []
    for name in ("_settle_known_threads", "_settle_known_serial"):
        kernel = getattr(tb, name)
        monkeypatch.setattr(tb, name, lambda *a, _k=kernel, _n=name: used.append(_n) or _k(*a))
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        tb.settle_known_many(Z, ph, 0, par, lv.cfg, lv.st.capture_tol, lv.table)
    finally:
        numba.set_num_threads(threads)
    tb.settle_known_many(Z, ph, 0, par, lv.cfg, lv.st.capture_tol, lv.table)
    assert used == ["_settle_known_serial",
                    "_settle_known_threads" if threads > 1 else "_settle_known_serial"]
