"""Issue 14, Atlas: progress counts the frequency points done inside running levels (not only
finished levels), on every backend, and the bar says so."""

import pytest

from contactvib import ContactModel
from contactvib.sweeps.backends import DaskBackend, LocalPool, run_levels
from contactvib.sweeps.resonance import _run_level, resonance_dataset
from contactvib.sweeps.sweep import SweepSettings, frequency_grid

ST = SweepSettings(fmin_hz=480.0, fmax_hz=520.0, df_hz=10.0, multistart_per_octave=1, n_starts=2)
LEVELS = (0.5, 0.6)


def _run(backend):
    """``(reports, finished)``: every ``(pa, points)`` the levels reported while running, and
    the levels in the order they finished."""
    reports, finished = [], []
    tasks = {pa: (ContactModel().parameters(), pa, ST.to_dict(), None, None, False) for pa in LEVELS}
    run_levels(tasks, _run_level, backend, lambda pa, result: finished.append(pa),
               lambda pa, points: reports.append((pa, points)))
    return reports, finished


def _check(reports, finished):
    n = frequency_grid(ST).size
    assert sorted(finished) == sorted(LEVELS)
    for pa in LEVELS:
        mine = [p for q, p in reports if q == pa]
        # half the grid after the sweeps, then the multi-start: points inside the running level
        assert any(0 < p < n for p in mine), (pa, mine)
        assert all(0 < p <= n for p in mine)


@pytest.mark.parametrize("backend", [LocalPool(1), LocalPool(2)], ids=["this-process", "pool-2"])
def test_levels_report_points_done_while_running(backend):
    _check(*_run(backend))


def test_dask_workers_report_points_done_while_running():
    reports, finished = _run(DaskBackend(n_workers=2))
    _check(reports, finished)


def test_bar_counts_points_and_levels(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("contactvib.sweeps.backends.kernel_cache_cold", lambda: False)
    resonance_dataset(ContactModel(), levels=list(LEVELS), settings=ST, out=tmp_path, name="atlas",
                      backend=LocalPool(1), progress=True)
    err = capsys.readouterr().err
    n = frequency_grid(ST).size
    assert "2/2 levels" in err and f"{2 * n}/{2 * n} f_e points" in err
    assert "f_e point" in err and "compiling" not in err  # warm cache: no compile notice


def test_local_cluster_workers_run_without_the_profiler():
    """``--dask-workers``: the LocalCluster's workers get LOCAL_CLUSTER_CONFIG (no statistical
    profiler sampling every thread every 10 ms: ~9 % of a 2-worker atlas slice's CPU)."""
    import dask

    from contactvib.sweeps.dask_worker import LOCAL_CLUSTER_CONFIG, open_client

    client, cluster, threads = open_client(DaskBackend(n_workers=1), timeout=3.0)
    try:
        got = client.run(lambda: {k: dask.config.get(k) for k in LOCAL_CLUSTER_CONFIG})
        assert list(got.values()) == [LOCAL_CLUSTER_CONFIG]
        assert dask.config.get("distributed.worker.profile.enabled") is True  # this process's own
    finally:
        client.close()
        cluster.close()


@pytest.mark.timing
@pytest.mark.parametrize("backend", [LocalPool(2), DaskBackend(n_workers=2)], ids=["pool-2", "dask-2"])
def test_levels_start_highest_first_as_workers_free_up(backend):
    """Every backend starts the levels in the order run_levels gives them (highest P_a, the
    slowest, first), each when a worker is free: the longest-first schedule. Level 0.9 takes six
    times as long as the others (3 s against 0.5 s); while it runs, the other worker takes 0.8,
    0.7, 0.6, 0.5 one after another (even if it joins up to ~1.5 s late). Dask's own placement
    (two levels per single-threaded worker from the start, before it sees how many are coming)
    queued 0.7 behind 0.9. ``time.sleep`` is the level: it only needs to be importable on the
    workers."""
    import time

    tasks = {0.9: (3.0,), 0.8: (0.5,), 0.7: (0.5,), 0.6: (0.5,), 0.5: (0.5,)}
    done = []  # the levels in the order their results arrive
    run_levels(tasks, time.sleep, backend, lambda pa, result: done.append(pa))
    assert [pa for pa in done if pa != 0.9] == [0.8, 0.7, 0.6, 0.5], done
    assert done.index(0.7) < done.index(0.9), done
