"""The kernels' on-disk cache folder: keyed by their sources (a stale kernel cannot be loaded), and
a writable temporary folder keyed the same way, with a warning, when the user's cache folder
cannot be written (never numba's cache inside the installed package)."""

import hashlib
import shutil
from pathlib import Path

import pytest

import contactvib._kernels
from contactvib._kernels import _sources_key, kernel_cache_dir


def test_kernel_cache_folder_is_keyed_by_the_sources(monkeypatch, tmp_path):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    folder = kernel_cache_dir()
    assert folder is not None and folder.is_dir()
    assert folder.parent == tmp_path / "contactvib" / "numba"
    # the name is the hash of the kernel sources, recomputed here independently
    kernels = Path(contactvib._kernels.__file__).parent
    digest = hashlib.sha256()
    for path in sorted(kernels.glob("*.py")):
        digest.update(path.name.encode() + path.read_bytes())
    assert folder.name == digest.hexdigest()[:16]
    assert kernel_cache_dir() == folder  # deterministic
    # an edited kernel (one byte in one file) gets another folder: no stale kernel is loaded
    copy = tmp_path / "kernels"
    shutil.copytree(kernels, copy, ignore=shutil.ignore_patterns("__pycache__"))
    flow = copy / "flow.py"
    flow.write_bytes(flow.read_bytes() + b"\n")
    other = kernel_cache_dir(copy)
    assert other is not None and other != folder and other.parent == folder.parent
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "mine"))
    assert kernel_cache_dir() is None  # the user's choice wins


def test_an_unwritable_cache_folder_falls_back_to_a_temporary_one(monkeypatch, tmp_path):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    blocker = tmp_path / "a_file"
    blocker.write_text("")  # a folder cannot be made below a regular file
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker / "cache"))
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path / "tmp"))
    with pytest.warns(RuntimeWarning, match="cannot be written: compiled kernels are cached in"):
        folder = kernel_cache_dir()
    key = _sources_key(Path(contactvib._kernels.__file__).parent)
    assert folder is not None and folder.name == key and folder.is_dir()
    assert folder.parent.parent == tmp_path / "tmp"
    # nothing writable at all: numba's own (no persistent cache), said too
    monkeypatch.setattr("tempfile.tempdir", str(blocker / "tmp"))
    with pytest.warns(RuntimeWarning, match="no writable folder for the kernel cache"):
        assert kernel_cache_dir() is None


def test_the_cli_prints_the_warning_as_one_line():
    from contactvib.cli.main import _warning_line

    line = _warning_line(RuntimeWarning("a\nb"), RuntimeWarning, "f.py", 1)
    assert line == "contactvib: warning: a\\nb\n"
