"""Numba's on-disk cache for the compiled kernels: where it is and when it is stale.

Numba keys a cached function on its own source file only (its modification
time and size): a compiled integrator in :mod:`liquidamp.coupled._kernels`
links the device physics of :mod:`liquidamp.device.kernels_model` and
:mod:`liquidamp.device.kernels_laws` in, and would keep a stale copy of them
after those files change.  Every module with cached kernels therefore calls
:func:`drop_stale` at import: a stamp (hash of every compiled source file,
:data:`COMPILED_SOURCES`) kept beside the module's cache files decides
whether they are dropped, so that any change to any kernel source recompiles
every kernel that may have inlined it.

The cache directory is numba's own choice (:func:`cache_dir`): the
``NUMBA_CACHE_DIR`` override, else ``__pycache__`` beside the source when
it is writable (an editable or a user-writable install), else the user-wide
cache directory (``~/.cache/numba/...``, for a read-only site-packages).

References
----------
.. [1] Numba documentation, "Notes on caching": "changes to other files the
   function depends on are not detected", numba.readthedocs.io.
"""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path

__all__ = ["COMPILED_SOURCES", "cache_dir", "drop_stale", "sources_stamp"]

_ROOT = Path(__file__).resolve().parent

#: Package-relative paths of every module with cached (``cache=True``) kernels.
COMPILED_SOURCES = (
    "device/kernels_layout.py",
    "device/kernels_laws.py",
    "device/kernels_base.py",
    "device/kernels_model.py",
    "coupled/_linalg.py",
    "coupled/_kernels.py",
    "coupled/_rotor_kernel.py",
    "analysis/response/_torus.py",
)


@cache
def sources_stamp() -> str:
    """Hash of every compiled source file (:data:`COMPILED_SOURCES`), hex.

    Examples
    --------
    >>> len(sources_stamp())
    64
    """
    h = hashlib.sha256()
    for rel in COMPILED_SOURCES:
        h.update(rel.encode())
        h.update((_ROOT / rel).read_bytes())
    return h.hexdigest()


def cache_dir(py_file: str | Path) -> Path | None:
    """The directory numba caches the kernels of source ``py_file`` in (None: no cache).

    Numba's locators in numba's order: ``NUMBA_CACHE_DIR``, ``__pycache__``
    beside the source if writable, the user-wide cache directory.

    Examples
    --------
    >>> from liquidamp.device import kernels_laws
    >>> cache_dir(kernels_laws.__file__) is not None
    True
    """
    from numba.core import caching

    for name in ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator"):
        cls = getattr(caching, name, None) or getattr(caching, "_" + name, None)
        if cls is None:  # pragma: no cover - another numba layout
            continue
        try:
            loc = cls.from_function(cache_dir, str(py_file))  # any function: its line only
        except (OSError, AttributeError, TypeError):  # pragma: no cover - unusable here
            loc = None
        if loc is not None:
            return Path(loc.get_cache_path())
    return None  # pragma: no cover - nowhere writable


def drop_stale(py_file: str | Path) -> None:
    """Delete the cache files of module ``py_file`` if any compiled source has changed.

    Called at the import of every module of :data:`COMPILED_SOURCES`; a
    read-only or missing cache directory leaves numba's own handling.
    """
    try:
        where = cache_dir(py_file)
        if where is None:
            return
        stem = Path(py_file).stem
        mark = where / f"{stem}.sources-stamp"
        stamp = sources_stamp()
        if mark.is_file() and mark.read_text() == stamp:
            return
        for f in where.glob(f"{stem}.*.nb[ic]"):
            f.unlink()
        where.mkdir(parents=True, exist_ok=True)
        mark.write_text(stamp)
    except OSError:  # pragma: no cover - a read-only cache: numba's own handling applies
        pass
