"""Old keyword names kept working (with a DeprecationWarning) after a rename.

One keyword name per quantity across the package: ``amplitude`` [m] (stroke
amplitude), ``frequency`` [Hz] and ``omega`` [rad/s] (the two frequencies
have two names, so neither needs a unit suffix), ``amplitudes`` /
``frequencies`` for arrays of them.  :func:`renamed` maps a function's former
names (``amplitude_m``, ``frequency_hz``, ...) onto the new ones.
"""

from __future__ import annotations

import functools
import warnings

__all__ = ["renamed"]


def renamed(**old_to_new: str):
    """Decorator: accept the keywords ``old_to_new`` under their new names, with a warning.

    Examples
    --------
    >>> @renamed(amplitude_m="amplitude")
    ... def f(*, amplitude):
    ...     return amplitude
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     f(amplitude_m=0.001), w[0].category.__name__
    (0.001, 'DeprecationWarning')
    >>> f(amplitude=0.001, amplitude_m=0.002)
    Traceback (most recent call last):
    ...
    TypeError: f() got both 'amplitude' and its former name 'amplitude_m'
    """
    def wrap(fn):
        @functools.wraps(fn)
        def inner(*args, **kwargs):
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{fn.__name__}() got both {new!r} and its former "
                                        f"name {old!r}")
                    warnings.warn(f"{fn.__name__}(): keyword {old!r} is now {new!r}",
                                  DeprecationWarning, stacklevel=2)
                    kwargs[new] = kwargs.pop(old)
            return fn(*args, **kwargs)

        return inner

    return wrap
