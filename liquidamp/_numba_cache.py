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

__all__ = ["COMPILED_SOURCES", "cache_dir", "drop_stale", "sources_stamp", "family",
           "compile_notices"]

_ROOT = Path(__file__).resolve().parent

#: Package-relative paths of every module with cached (``cache=True``) kernels.
COMPILED_SOURCES = (
    "device/kernels_layout.py",
    "device/kernels_laws.py",
    "device/kernels_base.py",
    "device/kernels_thermal.py",
    "device/kernels_position.py",
    "device/kernels_model.py",
    "device/kernels_stroke_map.py",
    "coupled/_linalg.py",
    "coupled/_stroke_kernels.py",
    "coupled/_kernels.py",
    "coupled/_rotor_kernel.py",
    "analysis/response/_torus.py",
    "analysis/stability/_map_kernel.py",
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
    global _KERNELS_IMPORTED
    _KERNELS_IMPORTED = True
    if _state["sink"] is not None:
        _listen()
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


# ---------------------------------------------------------------------------
# compile notices: one line per compiled family, while it compiles

#: Family of a compiled top-level function: (module, name predicate, words).
_FAMILIES = (
    ("liquidamp.coupled._kernels", lambda n: n.endswith("_plain"),
     "the time integrators of the base models"),
    ("liquidamp.coupled._kernels", lambda n: True,
     "the time integrators with add-on effects"),
    ("liquidamp.coupled._rotor_kernel", lambda n: True,
     "the rotor and blade integrator (DOP853)"),
    ("liquidamp.analysis.response._torus", lambda n: True,
     "the two-frequency harmonic balance"),
    ("liquidamp.coupled._linalg", lambda n: True, "the linear algebra kernels"),
    ("liquidamp.device.", lambda n: True, "the device model functions"),
)

_state = {"sink": None, "depth": 0, "said": set(), "listener": None}


def family(module: str, name: str) -> str | None:
    """The compiled family a kernel belongs to (the words of its notice), or None.

    Examples
    --------
    >>> family("liquidamp.coupled._kernels", "integrate_plain")
    'the time integrators of the base models'
    >>> family("liquidamp.device.kernels_model", "model_rhs")
    'the device model functions'
    """
    for mod, pred, words in _FAMILIES:
        if module.startswith(mod) and pred(name):
            return words
    return None


def compile_notices(sink) -> None:
    """Send one line per compiled family to ``sink`` (a callable, None: silent).

    Numba compiles a kernel the first time it is called with new argument
    types unless its cache holds it; the line says which family compiles
    while it does (``compiling the rotor and blade integrator (DOP853; once,
    cached) ...``), once per family and process.  The command line sets it
    (``--quiet`` does not); the library is silent by default.
    """
    _state["sink"] = sink
    if sink is not None and _KERNELS_IMPORTED:
        _listen()


#: Set by :func:`drop_stale`: a module with kernels (so numba) is imported.
_KERNELS_IMPORTED = False


def _listen() -> None:
    """Register the compile listener (once; numba is imported by then)."""
    if _state["listener"] is not None:
        return
    from numba.core import event

    class _Notices(event.Listener):
        def on_start(self, ev):
            depth = _state["depth"]
            _state["depth"] = depth + 1
            if depth or _state["sink"] is None:
                return
            f = ev.data["dispatcher"].py_func
            words = family(f.__module__, f.__name__)
            if words and words not in _state["said"]:
                _state["said"].add(words)
                _state["sink"](f"compiling {words} (once; cached for the next run) ...")

        def on_end(self, ev):
            _state["depth"] = max(_state["depth"] - 1, 0)

    _state["listener"] = _Notices()
    event.register("numba:compile", _state["listener"])
