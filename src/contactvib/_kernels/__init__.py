"""Compiled kernels (numba, ``cache=True``): arrays and scalars in, arrays and status codes out.

They know nothing of units, files or plots; the public modules validate, call and interpret.

On-disk cache: numba checks a cached function against its own source file only, not against the
kernels it calls from other files, so an edited ``flow.py`` would leave a stale ``settle_many``
in the cache. Unless ``NUMBA_CACHE_DIR`` is set, the kernels are therefore cached under
``$XDG_CACHE_HOME/contactvib/numba/<hash of this package's sources>`` (``~/.cache`` by default,
a temporary folder keyed the same way when that cannot be written): a change to any kernel, or a
new version of contactvib, compiles afresh.

Compile time (a first run compiles ~45 CPU s): every kernel is compiled for one argument-type
signature. numba would compile a separate copy of a callee for each integer or boolean constant
a kernel passes it (``Literal[int](4)``), so such constants are passed as ``np.int64(4)`` /
``np.bool_(False)``; and arrays are copied by loops, not slice assignments (which compile
numba's shape-error formatting, ~5 s). The small DOP853 helpers of ``flow.py`` keep their
constant stage counts and components on purpose (unrolled inner loops).
``tests/sweeps/test_compile_split.py`` checks it.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import warnings
from pathlib import Path


def _sources_key(sources: Path) -> str:
    """First 16 hex digits of the SHA-256 of every ``*.py`` file of ``sources`` (names and bytes)."""
    digest = hashlib.sha256()
    for path in sorted(sources.glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def _writable_folder(folder: Path) -> bool:
    """Create ``folder`` if needed and check that a file can be written in it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError:
        return False
    return True


def kernel_cache_dir(sources: Path | None = None) -> Path | None:
    """A cache folder keyed by the hash of every kernel source (the ``*.py`` files of
    ``sources``, default this package), or None to keep numba's own (``NUMBA_CACHE_DIR`` set).

    The folder is ``$XDG_CACHE_HOME/contactvib/numba/<key>`` (``~/.cache`` by default). When it
    cannot be written (a read-only or missing home, a full disk), the same key under the system's
    temporary folder is used instead, with a warning that says so: never numba's cache inside the
    installed package, where an edited kernel called from another file would not be recompiled.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    key = _sources_key(sources or Path(__file__).parent)
    try:
        home_cache = Path.home() / ".cache"
    except RuntimeError:  # no home directory known
        home_cache = None
    base = os.environ.get("XDG_CACHE_HOME") or home_cache
    preferred = Path(base) / "contactvib" / "numba" / key if base else None
    if preferred is not None and _writable_folder(preferred):
        return preferred
    fallback = Path(tempfile.gettempdir()) / f"contactvib-numba-{getattr(os, 'getuid', lambda: 0)()}" / key
    if _writable_folder(fallback):
        warnings.warn(f"the kernel cache folder {preferred} cannot be written: compiled kernels are "
                      f"cached in {fallback} instead (set XDG_CACHE_HOME to a writable folder)",
                      RuntimeWarning, stacklevel=2)
        return fallback
    warnings.warn(f"no writable folder for the kernel cache ({preferred}, {fallback}): the kernels "
                  "are compiled again in every process (set XDG_CACHE_HOME or NUMBA_CACHE_DIR)",
                  RuntimeWarning, stacklevel=2)
    return None


def _use_kernel_cache_dir() -> None:
    folder = kernel_cache_dir()
    if folder is not None:
        from numba.core import config

        config.CACHE_DIR = str(folder)


_use_kernel_cache_dir()
