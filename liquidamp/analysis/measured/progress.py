"""Progress of the fits: every model evaluation reported to a caller's callable.

:func:`fit_progress` (a context manager) and :func:`with_progress` (a decorator adding a
``progress=`` keyword) set the callable that the calibration's objective calls as
``progress(1)`` after every run of the model over all the records of one fit
(:func:`current_progress`); the command line passes a tqdm bar's ``update``.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools

__all__ = ["fit_progress", "with_progress", "current_progress"]

_PROGRESS = contextvars.ContextVar("liquidamp_fit_progress", default=None)


@contextlib.contextmanager
def fit_progress(progress):
    """Context manager: every model evaluation of the fits inside calls ``progress(1)``.

    Parameters
    ----------
    progress : callable or None
        E.g. a tqdm bar's ``update``; None does nothing.
    """
    if progress is None:
        yield
        return
    token = _PROGRESS.set(progress)
    try:
        yield
    finally:
        _PROGRESS.reset(token)


def with_progress(func):
    """Decorator: ``func(..., progress=None)`` runs inside :func:`fit_progress`.

    ``progress`` (optional callable) is called as ``progress(1)`` after every
    model evaluation (every run of the model over all the records of one fit).
    """

    @functools.wraps(func)
    def wrapper(*args, progress=None, **kwargs):
        with fit_progress(progress):
            return func(*args, **kwargs)

    return wrapper


def current_progress():
    """The callable set by :func:`fit_progress` in this context, or None.

    Examples
    --------
    >>> seen = []
    >>> with fit_progress(seen.append):
    ...     current_progress()(1)
    >>> seen, current_progress() is None
    ([1], True)
    """
    return _PROGRESS.get()
