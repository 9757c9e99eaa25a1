"""Resume and concurrency (issue 13, item 6): a resume with other settings is refused before
computing, each level has its own chunk, one run at a time writes into a folder (OUT/.lock), and
the temporary files of killed runs are removed."""

from __future__ import annotations

import fcntl
import os
import subprocess
import sys

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.model import ContactModel, ParameterError
from contactvib.sweeps.resonance import OutputLocked, ResumeMismatch, chunk_path, resonance_dataset
from contactvib.sweeps.sweep import SweepSettings


def _tiny(**kw):
    base = dict(fmin_hz=340.0, fmax_hz=360.0, df_hz=10.0, multistart_per_octave=0)
    base.update(kw)
    return SweepSettings(**base)


def _run(out, levels=(0.65,), resume=False, model=None, **kw):
    return resonance_dataset(model or ContactModel(), levels=list(levels), settings=_tiny(**kw), out=out, resume=resume,
                             workers=1, progress=False)


@pytest.fixture
def calls(monkeypatch):
    """The levels swept (trace_level calls) from now on."""
    import contactvib.sweeps.sweep as sweep

    real = sweep.trace_level
    seen = []
    monkeypatch.setattr(sweep, "trace_level",
                        lambda m, *, pa_over_q, settings: seen.append(pa_over_q) or real(m, pa_over_q=pa_over_q,
                                                                                           settings=settings))
    return seen


@pytest.fixture
def no_sweep(monkeypatch):
    """Fail if a level is swept."""
    import contactvib.sweeps.sweep as sweep

    def fail(*_a, **_k):
        raise AssertionError("a level was swept")

    monkeypatch.setattr(sweep, "trace_level", fail)


def _cli(out, *extra):
    return main(["resonance", "--pa", "0.65", "--fmin", "340", "--fmax", "360",
                 "--multistart-per-octave", "0", "--workers", "1", "--no-progress",
                 "--out", str(out), *extra])


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


# ------------------------------------------------------------------ resume with other settings

def test_resume_with_another_df_is_refused_before_computing(tmp_path, monkeypatch):
    _run(tmp_path, df_hz=10.0)
    chunk = chunk_path(tmp_path, 0.65)
    mtime = chunk.stat().st_mtime_ns
    import contactvib.sweeps.sweep as sweep

    monkeypatch.setattr(sweep, "trace_level", lambda *a, **k: pytest.fail("a level was swept"))
    with pytest.raises(ResumeMismatch) as e:
        _run(tmp_path, resume=True, df_hz=5.0)
    assert isinstance(e.value, ParameterError) and e.value.symbol == "resume"
    assert "df_hz = 10, not 5" in str(e.value) and str(chunk) in str(e.value)
    assert chunk.stat().st_mtime_ns == mtime
    # a requested level whose chunk was made otherwise refuses even among new levels
    with pytest.raises(ResumeMismatch, match="df_hz"):
        _run(tmp_path, levels=(0.6, 0.65), resume=True, df_hz=5.0)


def test_resume_with_another_model_is_refused(tmp_path, monkeypatch):
    _run(tmp_path)
    import contactvib.sweeps.sweep as sweep

    monkeypatch.setattr(sweep, "trace_level", lambda *a, **k: pytest.fail("a level was swept"))
    params = ContactModel().parameters()
    name = next(iter(params))
    other = ContactModel(**{**params, name: params[name] * 1.01})
    with pytest.raises(ResumeMismatch, match=f"made with {name} = "):
        _run(tmp_path, resume=True, model=other)


def test_without_resume_other_settings_recompute_and_overwrite(tmp_path, calls):
    _run(tmp_path, df_hz=10.0)
    calls.clear()
    _run(tmp_path, df_hz=5.0)
    assert calls == [0.65]
    calls.clear()
    _run(tmp_path, resume=True, df_hz=5.0)  # the overwritten chunk is now reused
    assert calls == []


def test_resume_with_the_same_settings_reuses_the_chunk(tmp_path, monkeypatch):
    first = _run(tmp_path)
    mtime = chunk_path(tmp_path, 0.65).stat().st_mtime_ns
    import contactvib.sweeps.sweep as sweep

    monkeypatch.setattr(sweep, "trace_level", lambda *a, **k: pytest.fail("a level was swept"))
    again = _run(tmp_path, resume=True)
    assert chunk_path(tmp_path, 0.65).stat().st_mtime_ns == mtime
    for name in ("fe_hz", "app_um", "period", "branch_index"):
        np.testing.assert_array_equal(first[name].values, again[name].values)
    assert first.attrs == again.attrs  # the chunk's own level attribute does not leak


def test_cli_resume_with_another_df_is_one_line_exit_2(tmp_path, capsys, monkeypatch):
    out = tmp_path / "res"
    assert _cli(out, "--df", "10", "--keep-chunks") == 0  # the chunks of a run to resume
    capsys.readouterr()
    import contactvib.sweeps.sweep as sweep

    monkeypatch.setattr(sweep, "trace_level", lambda *a, **k: pytest.fail("a level was swept"))
    assert _cli(out, "--df", "5", "--resume") == 2
    err = _one_error_line(capsys)
    assert err == (f"contactvib: error: --resume: {chunk_path(out, 0.65)} was made with df_hz = 10, "
                   "not 5 (use another --out, or delete the chunk)")
    assert _cli(out, "--df", "10", "--resume") == 0  # same settings: reused, lock released


# ------------------------------------------------------------------ one chunk per level

def test_close_levels_get_their_own_chunks(tmp_path, calls):
    assert chunk_path(tmp_path, 0.5).name == "level_pa0.5.nc"
    assert chunk_path(tmp_path, 0.65).name == "level_pa0.65.nc"
    assert chunk_path(tmp_path, 0.5) != chunk_path(tmp_path, 0.5000004)
    _run(tmp_path, levels=(0.5,))
    calls.clear()
    ds = _run(tmp_path, levels=(0.5000004,), resume=True)
    assert calls == [0.5000004]
    assert np.all(ds["pa_over_q"].values == 0.5000004)
    assert chunk_path(tmp_path, 0.5).is_file() and chunk_path(tmp_path, 0.5000004).is_file()


def test_a_chunk_of_another_level_is_not_reused(tmp_path, calls):
    _run(tmp_path, levels=(0.5,))
    os.replace(chunk_path(tmp_path, 0.5), chunk_path(tmp_path, 0.6))  # renamed by hand
    calls.clear()
    ds = _run(tmp_path, levels=(0.6,), resume=True)
    assert calls == [0.6] and np.all(ds["pa_over_q"].values == 0.6)


# ------------------------------------------------------------------ one run per folder

def _held_lock(out):
    out.mkdir(parents=True, exist_ok=True)
    f = open(out / ".lock", "a+")
    fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    return f


def test_a_held_lock_refuses_a_second_run_at_once(tmp_path, no_sweep):
    f = _held_lock(tmp_path)
    try:
        with pytest.raises(OutputLocked) as e:
            _run(tmp_path)
        assert isinstance(e.value, ParameterError) and e.value.symbol == "out"
        assert "another contactvib run is writing there" in str(e.value)
    finally:
        f.close()
    assert not (tmp_path / "resonance.nc").exists()


def test_cli_a_held_lock_is_one_line_exit_2(tmp_path, capsys, no_sweep):
    out = tmp_path / "res"
    f = _held_lock(out)
    try:
        assert _cli(out, "--df", "10") == 2
    finally:
        f.close()
    assert _one_error_line(capsys) == (f"contactvib: error: --out = {out}: another contactvib run "
                                       f"is writing there ({out / '.lock'})")


def test_cli_paper_a_held_lock_is_one_line_exit_2(tmp_path, capsys, no_sweep):
    out = tmp_path / "paper"
    f = _held_lock(out)
    try:
        assert main(["paper", "--out", str(out), "--fmin", "340", "--fmax", "360", "--df", "10",
                     "--multistart-per-octave", "0", "--workers", "1", "--no-progress"]) == 2
    finally:
        f.close()
    assert "another contactvib run is writing there" in _one_error_line(capsys)


def test_the_lock_is_released_after_an_error(tmp_path, monkeypatch):
    import contactvib.sweeps.sweep as sweep

    def boom(*_a, **_k):
        raise RuntimeError("boom")

    monkeypatch.setattr(sweep, "trace_level", boom)
    with pytest.raises(RuntimeError):
        _run(tmp_path)
    _held_lock(tmp_path).close()  # free again


# ------------------------------------------------------------------ stale temporary files

def test_stale_temporaries_of_dead_runs_are_removed(tmp_path):
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    dead = proc.pid
    (tmp_path / ".chunks").mkdir()
    stale = [tmp_path / f".resonance.nc.tmp{dead}", tmp_path / ".chunks" / f".level_pa0.6.nc.tmp{dead}"]
    mine = tmp_path / ".chunks" / f".level_pa0.7.nc.tmp{os.getpid()}"  # another level
    other = tmp_path / "notes.tmp1"  # not a contactvib temporary
    for p in (*stale, mine, other):
        p.write_bytes(b"partial")
    _run(tmp_path)
    assert not any(p.exists() for p in stale)
    assert mine.is_file() and other.is_file()
