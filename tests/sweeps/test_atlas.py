"""``contactvib atlas`` (issue 14, "Atlas" and "Scale-out"): the same files whichever backend ran
them (local pool, ``--dask-workers 2``, a running LocalCluster through ``--scheduler``), each level
equal to ``resonance``'s, resumable after Ctrl-C on another backend, compressed, and bad input
refused in one line."""

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import contactvib
from chunks_wait import first_chunk
from contactvib.cli import main

LEVELS = ["0.3", "0.4", "0.5"]
GRID = ["--fmin", "300", "--fmax", "400", "--df", "10", "--multistart-per-octave", "2", "--starts", "4",
        "--no-progress"]
RANGE = ["--pa-min", "0.3", "--pa-max", "0.5", "--npa", "3"]
_ENV = dict(os.environ, PYTHONPATH=os.pathsep.join(
    [str(Path(contactvib.__file__).resolve().parents[1])]
    + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))


def _atlas(out: Path, *extra, capsys=None) -> xr.Dataset:
    rc = main(["atlas", *RANGE, *GRID, "--out", str(out), *extra])
    if capsys is not None:
        err = capsys.readouterr().err
        assert rc == 0, err
    assert rc == 0
    return xr.load_dataset(out / "atlas.nc")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The atlas on the default backend (the local process pool)."""
    out = tmp_path_factory.mktemp("atlas_pool")
    return out, _atlas(out, "--keep-chunks")


def test_levels_chunks_and_compression(reference):
    out, ds = reference
    assert sorted(np.unique(ds["pa_over_q"].values)) == [0.3, 0.4, 0.5]
    assert sorted(p.name for p in (out / ".chunks").glob("level_pa*.nc")) == [
        "level_pa0.3.nc", "level_pa0.4.nc", "level_pa0.5.nc"]
    for path in [out / "atlas.nc", *(out / ".chunks").glob("level_pa*.nc")]:
        with xr.open_dataset(path) as d:
            enc = d["app_um"].encoding
            assert enc["zlib"] and enc["complevel"] == 4 and enc["shuffle"], path
            assert enc["chunksizes"] == (min(4096, d.sizes["point"]),)
            assert d["harmonics_um"].encoding["chunksizes"][1] == d.sizes["harmonic"]
    # one level read lazily from atlas.nc without loading the others
    with xr.open_dataset(out / "atlas.nc") as d:
        lazy = d.where(d["pa_over_q"] == 0.4, drop=True)["app_um"].values
    assert np.array_equal(lazy, ds["app_um"].values[ds["pa_over_q"].values == 0.4])


def test_dask_local_cluster_gives_identical_files(reference, tmp_path):
    """The same atlas on Dask; a complete run removes its chunks (atlas.nc holds every level)."""
    _out, ds = reference
    assert _atlas(tmp_path / "dask", "--dask-workers", "2").identical(ds)
    assert not (tmp_path / "dask" / ".chunks").exists()


def test_running_scheduler_gives_identical_files(reference, tmp_path, monkeypatch):
    """A running cluster (its workers in another working directory: a relative --out is this
    process's) gives the same atlas, its chunks written where this process's --out is."""
    from distributed import LocalCluster

    _out, ds = reference
    (tmp_path / "cluster").mkdir()
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "cluster")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        monkeypatch.chdir(tmp_path / "here")
        got = _atlas(Path("sched"), "--scheduler", cluster.scheduler_address, "--keep-chunks")
    assert got.identical(ds)
    assert len(list((tmp_path / "here" / "sched" / ".chunks").glob("level_pa*.nc"))) == 3
    assert not (tmp_path / "cluster" / "sched").exists()


def test_each_level_equals_resonance(reference, tmp_path):
    """The atlas's level is resonance's level, value for value (chunk for chunk)."""
    out, ds = reference
    res = tmp_path / "res"
    assert main(["resonance", "--pa", "0.4", *GRID, "--workers", "1", "--out", str(res), "--keep-chunks"]) == 0
    a = xr.load_dataset(out / ".chunks" / "level_pa0.4.nc")
    r = xr.load_dataset(res / ".chunks" / "level_pa0.4.nc")
    assert a.identical(r)
    merged = xr.load_dataset(res / "resonance.nc")
    at = ds["pa_over_q"].values == 0.4
    for name in ("fe_hz", "app_um", "ymin_um", "period", "floquet_re", "harmonics_um", "resonance"):
        np.testing.assert_array_equal(ds[name].values[at], merged[name].values, err_msg=name)  # NaN == NaN


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")
def test_resume_after_sigint_on_another_backend(reference, tmp_path, capsys):
    """Interrupted on the local pool (one line, exit 130), resumed on a Dask LocalCluster: the
    kept chunks are reused untouched and the atlas equals the uninterrupted one."""
    _out, ds = reference
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "contactvib", "atlas", "--pa", *LEVELS, *GRID, "--workers", "1",
                          "--out", str(out)], env=_ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    first_chunk(p, out)
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == 130, stderr
    kept = {c: c.stat().st_mtime_ns for c in (out / ".chunks").glob("level_pa*.nc")}
    assert 1 <= len(kept) < len(LEVELS)
    word = "level" if len(kept) == 1 else "levels"
    assert stderr == (f"contactvib: interrupted: {len(kept)} {word} kept in {out / '.chunks'}; "
                      "rerun with --resume\n")
    got = _atlas(out, "--resume", "--dask-workers", "2", "--keep-chunks", capsys=capsys)
    assert {c: c.stat().st_mtime_ns for c in kept} == kept
    assert got.identical(ds)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("args, option", [
    (["--npa", "0"], "--npa"),
    (["--npa", "2.5"], "--npa"),
    (["--pa-min", "0.6", "--pa-max", "0.5"], "--pa-min"),
    (["--pa-min", "-1"], "--pa-min"),
    (["--pa", "0.5", "--npa", "3"], "--pa"),
    (["--dask-workers", "0"], "--dask-workers"),
    (["--dask-workers", "2", "--scheduler", "tcp://127.0.0.1:8786"], "--dask-workers"),
    (["--workers", "2", "--dask-workers", "2"], "--workers"),
    (["--scheduler", "not an address"], "--scheduler"),
    (["--scheduler", "tcp://127.0.0.1:99999"], "--scheduler"),
])
def test_bad_input_one_line(args, option, tmp_path, capsys):
    rc = main(["atlas", "--fmin", "300", "--fmax", "400", "--df", "10", "--out", str(tmp_path / "o"), *args])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith(f"contactvib: error: {option}"), err


@pytest.mark.timing
def test_unreachable_scheduler_one_line_quickly(tmp_path, capsys):
    address = f"tcp://127.0.0.1:{_free_port()}"
    t0 = time.perf_counter()
    rc = main(["atlas", "--pa", "0.5", *GRID, "--out", str(tmp_path / "o"), "--scheduler", address])
    elapsed = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err == f"contactvib: error: --scheduler = {address}: no Dask scheduler answers there within 3 s\n"
    assert elapsed < 10
    assert not list((tmp_path / "o").glob(".chunks/*.nc"))


def test_atlas_levels():
    from contactvib.model import ParameterError
    from contactvib.sweeps.atlas import atlas_levels

    assert atlas_levels(0.05, 1.0, 96)[:3] == [0.05, 0.06, 0.07]
    assert len(atlas_levels(0.05, 1.0, 96)) == 96 and atlas_levels(0.05, 1.0, 96)[-1] == 1.0
    assert atlas_levels(0.1, 0.3, 3) == [0.1, 0.2, 0.3]  # rounded: 0.30000000000000004 -> 0.3
    assert atlas_levels(0.5, 0.5, 1) == [0.5]
    for args, symbol in (((0.5, 0.6, 1), "npa"), ((0.6, 0.5, 2), "pa_min"), ((0, 1, 2), "pa_min"),
                         ((0.5, float("nan"), 2), "pa_max")):
        with pytest.raises(ParameterError) as e:
            atlas_levels(*args)
        assert e.value.symbol == symbol


def test_kernel_cache_cold_reads_the_index_files(tmp_path, monkeypatch):
    from contactvib.sweeps import backends

    monkeypatch.setattr("contactvib._kernels.kernel_cache_dir", lambda: tmp_path)
    assert backends.kernel_cache_cold()
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "flow.settle-1.py311.nbi").write_bytes(b"")
    assert not backends.kernel_cache_cold()


def test_progress_counts_points_and_announces_a_cold_cache(tmp_path, monkeypatch, capsys):
    from contactvib import ContactModel
    from contactvib.sweeps.backends import LocalPool
    from contactvib.sweeps.resonance import COMPILING_MESSAGE, resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    monkeypatch.setattr("contactvib.sweeps.backends.kernel_cache_cold", lambda: True)
    st = SweepSettings(fmin_hz=490.0, fmax_hz=510.0, df_hz=10.0, multistart_per_octave=1, n_starts=2)
    resonance_dataset(ContactModel(), levels=[0.5], settings=st, out=tmp_path, name="atlas", backend=LocalPool(1),
                      progress=True)
    err = capsys.readouterr().err
    assert COMPILING_MESSAGE in err
    assert "3/3 f_e points" in err and "atlas" in err


def test_query_reads_a_folder(reference, tmp_path, capsys):
    import json

    out, ds = reference
    assert main(["query", str(out), "--pa", "0.4", "--fe", "350", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["pa_over_q"] == 0.4 and d["fe_hz"] == 350.0
    assert len(d["attractors"]) == int(((ds["pa_over_q"] == 0.4) & (ds["fe_hz"] == 350.0)).sum())
    assert main(["query", str(tmp_path), "--pa", "0.4", "--fe", "350"]) == 2
    err = capsys.readouterr().err
    assert err == (f"contactvib: error: DATASET = {tmp_path}: a folder without atlas.nc, paper.nc "
                   "or resonance.nc\n")


def _session(sid: int) -> set:
    """Live (not zombie) processes of session ``sid`` (from /proc)."""
    found = set()
    for d in Path("/proc").iterdir():
        try:
            stat = (d / "stat").read_text() if d.name.isdigit() else ""
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split() if stat else []
        if fields and int(fields[3]) == sid and fields[0] not in "ZX":
            found.add(int(d.name))
    return found


@pytest.mark.timing
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")
def test_sigkill_on_a_local_cluster_leaves_no_process(tmp_path):
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "contactvib", "atlas", "--pa", *LEVELS, *GRID, "--dask-workers", "2",
                          "--out", str(out)], env=_ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, start_new_session=True)
    first_chunk(p, out)
    assert len(_session(p.pid)) >= 3  # this run, its two Dask workers (and the resource tracker)
    p.kill()
    _stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == -signal.SIGKILL and stderr == ""
    deadline = time.monotonic() + 15
    while _session(p.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _session(p.pid)
    for chunk in (out / ".chunks").glob("level_pa*.nc"):  # every chunk there is complete
        with xr.open_dataset(chunk) as d:
            assert d.sizes["point"] > 0 and float(d.attrs["chunk_pa_over_q"]) in (0.3, 0.4, 0.5)
