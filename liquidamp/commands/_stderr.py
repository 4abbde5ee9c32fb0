"""Standard error: warnings (each once, without a source line) and progress (one tqdm style).

Nothing here imports numpy, scipy, matplotlib or numba.
"""

from __future__ import annotations

import sys

__all__ = ["collect_warnings", "print_warnings", "warn_once", "route_warnings",
           "progress_bar", "working", "show_progress", "progress_lines"]


def collect_warnings(data) -> list[str]:
    """Every string of every ``"warnings"`` list in a nested JSON-ready ``data``, in order.

    Parameters
    ----------
    data : dict or list
        JSON-ready result (dicts, lists, scalars).

    Returns
    -------
    list of str
        Each warning once, in the order met.

    Examples
    --------
    >>> collect_warnings({"warnings": ["a"], "steps": [{"warnings": ["b", "a"]}]})
    ['a', 'b']
    """
    out: list[str] = []

    def walk(obj):
        if isinstance(obj, dict):
            for key, value in obj.items():
                if key == "warnings" and isinstance(value, (list, tuple)):
                    out.extend(str(w) for w in value if str(w) not in out)
                else:
                    walk(value)
        elif isinstance(obj, (list, tuple)):
            for value in obj:
                walk(value)

    walk(data)
    return list(dict.fromkeys(out))


def print_warnings(command: str, data) -> None:
    """Print each warning of ``data`` (see :func:`collect_warnings`) as one stderr line.

    Parameters
    ----------
    command : str
        Command name for the ``liquidamp COMMAND: warning: ...`` prefix.
    data : dict
        JSON-ready result.
    """
    for w in collect_warnings(data):
        warn_once(command, w)


#: Warnings printed by this process (each is printed once).
_PRINTED: set = set()


def _key(text: str) -> str:
    return " ".join(str(text).split()).rstrip(".").lower()


def warn_once(command: str, text: str) -> None:
    """Print ``liquidamp COMMAND: warning: TEXT`` on stderr unless this text was printed.

    Python warnings of the library (``warnings.warn``) are routed here by
    :func:`route_warnings`, so a warning that is both raised and stored in
    the result's ``"warnings"`` list is printed once, without a source line.
    """
    k = _key(text)
    if any(k == p or (len(p) > 30 and (p in k or k in p)) for p in _PRINTED):
        return
    _PRINTED.add(k)
    clear = "\r\x1b[K" if show_progress() else ""  # over a progress bar's line
    print(f"{clear}liquidamp {command}: warning: {' '.join(str(text).split())}",
          file=sys.stderr)


def route_warnings(command: str):
    """Context manager: every Python warning is printed once by :func:`warn_once`.

    Examples
    --------
    >>> import warnings
    >>> with route_warnings("demo"):
    ...     warnings.warn("same")
    ...     warnings.warn("same")
    """
    import contextlib
    import warnings

    @contextlib.contextmanager
    def ctx():
        from liquidamp.errors import LiquidampWarning

        _PRINTED.clear()  # once per command run
        with warnings.catch_warnings():
            warnings.simplefilter("always", LiquidampWarning)  # the others: Python's filters
            warnings.showwarning = lambda message, *a, **k: warn_once(command, str(message))
            yield

    return ctx()


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass

    def set_postfix_str(self, text: str) -> None:
        pass

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def progress_bar(total: int, desc: str, quiet: bool = False):
    """A tqdm progress bar on stderr, or a do-nothing bar.

    The bar is shown only when stderr is a terminal, ``quiet`` is False and
    tqdm is installed.  Use as a context manager; ``update(n)`` advances it.

    Parameters
    ----------
    total : int
        Number of steps.
    desc : str
        Label of the bar.
    quiet : bool
        Never show the bar (``--quiet``).

    Returns
    -------
    tqdm.tqdm or a do-nothing object with the same ``update``/``close``

    Examples
    --------
    >>> with progress_bar(3, "points", quiet=True) as bar:
    ...     bar.update()
    """
    if not show_progress(quiet):
        return _NoBar()
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return _NoBar()
    return tqdm(total=total, desc=desc, file=sys.stderr, leave=False, dynamic_ncols=True)


def working(desc: str, quiet: bool = False):
    """Context manager: a tqdm bar with the elapsed time for work without steps to count.

    Shown on a terminal only and not with ``quiet``; a daemon thread refreshes it
    twice a second.  Used where the library reports no progress (one steady state,
    a host sweep).

    Examples
    --------
    >>> with working("steady state", quiet=True):
    ...     pass
    """
    import contextlib
    import threading

    @contextlib.contextmanager
    def ctx():
        bar = progress_bar(None, desc, quiet)
        if isinstance(bar, _NoBar):
            yield bar
            return
        stop = threading.Event()

        def tick():
            while not stop.wait(0.5):
                bar.refresh()

        t = threading.Thread(target=tick, daemon=True)
        t.start()
        try:
            yield bar
        finally:
            stop.set()
            t.join()
            bar.close()

    return ctx()


def show_progress(quiet: bool = False) -> bool:
    """True if progress is shown: stderr is a terminal and not ``--quiet``."""
    return not quiet and bool(getattr(sys.stderr, "isatty", lambda: False)())


def progress_lines(quiet: bool = False, desc: str = "steps"):
    """A ``progress(message)`` callable for stage-wise work, drawn as one tqdm bar.

    Each call advances the bar by one step and shows ``message`` beside it;
    on a terminal only and not with ``quiet`` (else it does nothing).  The
    returned callable has ``close()``.
    """
    bar = progress_bar(None, desc, quiet)

    def progress(message: str = "", n: int = 1) -> None:
        if message:
            bar.set_postfix_str(str(message)[:60])
        bar.update(n)

    progress.close = bar.close
    return progress


