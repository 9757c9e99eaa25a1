"""Compiled kernels (numba, ``cache=True``): arrays and scalars in, arrays and status codes out.

They know nothing of units, files or plots; the public modules validate, call and interpret.

On-disk cache: numba checks a cached function against its own source file only, not against the
kernels it calls from other files, so an edited ``flow.py`` would leave a stale ``settle_many``
in the cache. Unless ``NUMBA_CACHE_DIR`` is set, the kernels are therefore cached under
``$XDG_CACHE_HOME/contactvib/numba/<hash of this package's sources>`` (``~/.cache`` by default):
a change to any kernel, or a new version of contactvib, compiles afresh.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def _kernel_cache_dir(sources: Path | None = None) -> Path | None:
    """A cache folder keyed by the hash of every kernel source (the ``*.py`` files of
    ``sources``, default this package), or None to keep numba's own."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    digest = hashlib.sha256()
    for path in sorted((sources or Path(__file__).parent).glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = base / "contactvib" / "numba" / digest.hexdigest()[:16]
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    if not os.access(folder, os.W_OK):
        return None
    return folder


def _use_kernel_cache_dir() -> None:
    folder = _kernel_cache_dir()
    if folder is not None:
        from numba.core import config

        config.CACHE_DIR = str(folder)


_use_kernel_cache_dir()
