"""Interrupts of ``contactvib resonance`` (issue 13): SIGINT and SIGKILL during the sweeps, with
one and two workers, leave no process behind; SIGINT prints one line and exits 130; ``--resume``
then gives the dataset of an uninterrupted run."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr

import contactvib
from chunks_wait import first_chunk
from contactvib import ContactModel

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")

LEVELS = (0.3, 0.4, 0.5)
GRID = dict(fmin_hz=300.0, fmax_hz=500.0, df_hz=4.0)
ARGS = ["resonance", "--pa", *map(str, LEVELS), "--fmin", "300", "--fmax", "500", "--df", "4",
        "--no-progress"]
_ENV = dict(os.environ, PYTHONPATH=os.pathsep.join(
    [str(Path(contactvib.__file__).resolve().parents[1])]
    + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))


def _contactvib(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "contactvib", *ARGS, *args], env=_ENV,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def _processes() -> dict:
    """pid -> (parent pid, start time, state) of every live process (from /proc)."""
    procs = {}
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()  # after "pid (name) "
        procs[int(d.name)] = (int(fields[1]), fields[19], fields[0])
    return procs


def _descendants(pid: int) -> set:
    """(pid, start time) of every live descendant of ``pid``."""
    procs = _processes()
    found, todo = set(), [pid]
    while todo:
        parent = todo.pop()
        for p, (pp, start, _state) in procs.items():
            if pp == parent and (p, start) not in found:
                found.add((p, start))
                todo.append(p)
    return found


def _gone(members: set, wait: float = 10.0) -> set:
    """The processes of ``members`` still running (not zombies) after up to ``wait`` s."""
    deadline = time.monotonic() + wait
    while True:
        procs = _processes()
        alive = {(p, s) for p, s in members if p in procs and procs[p][1] == s
                 and procs[p][2] not in "ZX"}
        if not alive or time.monotonic() > deadline:
            return alive
        time.sleep(0.1)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted dataset (in this process)."""
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    out = tmp_path_factory.mktemp("reference")
    resonance_dataset(ContactModel(), levels=LEVELS, settings=SweepSettings(**GRID), out=out, workers=1, progress=False)
    return xr.load_dataset(out / "resonance.nc")


def _resumed_equals(reference, out: Path):
    """``--resume`` reuses the kept chunks, completes and gives the uninterrupted dataset (in
    one process: the pool is what the interrupted runs test)."""
    kept = {c: c.stat().st_mtime_ns for c in (out / ".chunks").glob("level_pa*.nc")}
    p = _contactvib("--out", str(out), "--workers", "1", "--resume", "--keep-chunks")  # kept: compared below
    stdout, stderr = p.communicate(timeout=300)
    assert p.returncode == 0, stderr
    assert stderr == ""
    assert all(c.stat().st_mtime_ns == t for c, t in kept.items())  # reused, not recomputed
    assert xr.load_dataset(out / "resonance.nc").identical(reference)


@pytest.mark.timing
@pytest.mark.parametrize("workers", ["1", "2"])
def test_sigint_one_line_130_no_process_and_resume(tmp_path, reference, workers):
    out = tmp_path / "out"
    p = _contactvib("--out", str(out), "--workers", workers)
    first_chunk(p, out)
    family = _descendants(p.pid)
    p.send_signal(signal.SIGINT)
    t0 = time.monotonic()
    stdout, stderr = p.communicate(timeout=60)
    assert time.monotonic() - t0 < 20
    assert p.returncode == 130, stderr
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    n = len(list((out / ".chunks").glob("level_pa*.nc")))
    assert 1 <= n < len(LEVELS)  # interrupted in the middle, running levels not waited for
    word = "level" if n == 1 else "levels"
    assert lines[0] == (f"contactvib: interrupted: {n} {word} kept in {out / '.chunks'}; "
                        "rerun with --resume")
    assert stdout == ""
    assert not _gone(family)
    _resumed_equals(reference, out)


@pytest.mark.parametrize("workers", ["1", "2"])
def test_sigkill_leaves_no_process_and_resume(tmp_path, reference, workers):
    out = tmp_path / "out"
    p = _contactvib("--out", str(out), "--workers", workers)
    first_chunk(p, out)
    family = _descendants(p.pid)
    if workers == "2":
        assert len(family) >= 2  # the workers (and multiprocessing's resource tracker)
    p.kill()
    _stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == -signal.SIGKILL
    assert stderr == ""  # nothing from the workers nor from multiprocessing's resource tracker
    assert not _gone(family)  # the workers end with their parent
    _resumed_equals(reference, out)


# ------------------------------------------------------------------ in this process (library)

def _numba_frame():
    """A frame whose code lies in a ``numba`` folder (as numba's call-backs into Python)."""
    ns: dict = {}
    exec(compile("import sys\nframe = sys._getframe()", os.path.join(os.sep, "x", "numba", "f.py"),
                 "exec"), ns)
    return ns["frame"]


def test_deferred_sigint_only_defers_inside_numba():
    from contactvib.interrupts import check_interrupt, deferred_sigint

    with pytest.raises(KeyboardInterrupt):  # Python code on the stack: at once
        with deferred_sigint():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(100):
                time.sleep(0.01)
            pytest.fail("SIGINT not raised")
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    with pytest.raises(KeyboardInterrupt):
        with deferred_sigint():
            signal.getsignal(signal.SIGINT)(signal.SIGINT, _numba_frame())  # only a flag
            check_interrupt()  # raised where Python regains control
            pytest.fail("check_interrupt did not raise")
    with pytest.raises(KeyboardInterrupt):  # not checked inside: raised at the end of the block
        with deferred_sigint():
            signal.getsignal(signal.SIGINT)(signal.SIGINT, _numba_frame())
    check_interrupt()  # nothing pending any more


def test_check_interrupt_raises_under_a_set_stop_scope_flag_in_its_thread_only():
    import threading

    import numpy as np

    from contactvib.interrupts import check_interrupt, stop_scope

    flag = np.zeros(1, np.int64)
    with stop_scope(flag):
        check_interrupt()  # cleared: nothing
        flag[0] = 1
        other = []
        t = threading.Thread(target=lambda: other.append(check_interrupt()))  # another thread: no scope
        t.start()
        t.join()
        assert other == [None]
        with pytest.raises(KeyboardInterrupt):
            check_interrupt()
    check_interrupt()  # outside the scope: nothing


def test_library_interrupted_keeps_finished_levels_and_releases_lock(tmp_path):
    """SIGINT in this process after the first level (workers 1): Interrupted before the next
    level, one level kept, the lock released."""
    from contactvib.sweeps.resonance import Interrupted, output_lock, resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    def first_level_done(model, ds):
        if float(ds["pa_over_q"].values[0]) == LEVELS[0]:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(Interrupted) as e:
        resonance_dataset(ContactModel(), levels=LEVELS, settings=SweepSettings(**GRID), out=tmp_path, workers=1,
                          progress=False, on_level=first_level_done, level_results={})
    assert isinstance(e.value, KeyboardInterrupt)
    assert e.value.chunks == tmp_path / ".chunks"
    assert e.value.n_kept == 1 == len(list((tmp_path / ".chunks").glob("level_pa*.nc")))
    assert str(e.value) == f"interrupted: 1 level kept in {tmp_path / '.chunks'}; rerun with resume=True"
    assert not (tmp_path / "resonance.nc").exists()
    with output_lock(tmp_path):  # released
        pass


@pytest.mark.timing
def test_sigint_inside_the_parallel_kernel_is_no_systemerror(monkeypatch):
    """SIGINT while ``settle_known_many`` runs in this thread is honoured as the call returns,
    not in it: that parallel kernel calls back into Python (``_numba_unpickle``), and a KeyboardInterrupt
    raised there came out as ``SystemError: CPUDispatcher(...) returned a result with an
    exception set`` (issue 13)."""
    import threading

    import contactvib._kernels.table as table
    from contactvib.sweeps.resonance import Interrupted, resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    kernel, calls = table.settle_known_many, []

    def interrupted_kernel(*args):
        if not calls:  # the signal arrives while the kernel runs (one call: ~0.2 s)
            threading.Timer(0.03, lambda: len(calls) == 1 and os.kill(os.getpid(), signal.SIGINT)).start()
        calls.append(time.monotonic())
        out = kernel(*args)
        calls.append(time.monotonic())
        return out

    monkeypatch.setattr(table, "settle_known_many", interrupted_kernel)
    st = SweepSettings(fmin_hz=300.0, fmax_hz=340.0, df_hz=20.0, multistart_per_octave=40.0,
                       n_starts=600)
    with pytest.raises(Interrupted) as e:
        resonance_dataset(ContactModel(), levels=[0.9], settings=st, workers=1, progress=False)
    t_end = time.monotonic()
    assert e.value.chunks is None and str(e.value) == "interrupted"
    # raised as the first call returned, or (numba was on the stack) at the next check after it
    assert len(calls) == 1 or (len(calls) == 2 and t_end - calls[1] < 1.0)


@pytest.mark.parametrize("prctl", [True, False])
def test_worker_ends_with_its_killed_parent(tmp_path, prctl):
    """``end_with_parent``: PR_SET_PDEATHSIG, or (elsewhere) the thread polling the parent id."""
    child = ("import os, sys, time\n"
             "import contactvib.interrupts as i\n"
             f"if not {prctl}:\n"
             "    i._prctl_pdeathsig = lambda sig: False\n"
             "i.end_with_parent(os.getppid())\n"
             "print('ready', flush=True)\n"
             "time.sleep(60)\n")
    parent = ("import subprocess, sys, time\n"
              f"c = subprocess.Popen([sys.executable, '-c', {child!r}], stdout=subprocess.PIPE, text=True)\n"
              "assert c.stdout.readline() == 'ready\\n'\n"
              "print(c.pid, flush=True)\n"
              "time.sleep(60)\n")
    p = subprocess.Popen([sys.executable, "-c", parent], env=_ENV, stdout=subprocess.PIPE, text=True)
    pid = int(p.stdout.readline())
    family = {(q, s) for q, s in _descendants(p.pid) if q == pid}
    assert family
    p.kill()
    p.wait()
    assert not _gone(family, wait=5.0)
