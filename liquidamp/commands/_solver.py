"""Solver flags shared by every command that integrates: ``--rtol``, ``--engine``,
``--compiled-method``.

A command registers them with :func:`add_solver_arguments` under the name of
the preset of :data:`liquidamp.options.PRESETS` that the library function it
calls uses by default, and turns them into options with
:func:`solver_options`.  Without any flag the command passes ``None``, so the
library resolves its own documented preset: the command line and the library
cannot drift apart.  A flag overrides that one value of the same preset.
"""

from __future__ import annotations

from liquidamp.errors import ParameterError
from liquidamp.options import (
    COMPILED_METHODS,
    ENGINE_ALIASES,
    ENGINES,
    RTOL_RANGE,
    SolverOptions,
)

__all__ = ["add_solver_arguments", "solver_options", "SOLVER_FLAGS"]

#: argparse destination -> command-line flag, the SolverOptions fields the flags set.
SOLVER_FLAGS = {"rtol": "--rtol", "engine": "--engine", "compiled_method": "--compiled-method"}


def add_solver_arguments(parser, purpose: str = "default") -> None:
    """Add ``--rtol``, ``--engine`` and ``--compiled-method`` to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    purpose : str
        The preset (:func:`liquidamp.options.preset_names`) of the library
        function the command calls; its values are the defaults shown in the
        help.

    Examples
    --------
    >>> import argparse
    >>> p = argparse.ArgumentParser()
    >>> add_solver_arguments(p, "fit")
    >>> solver_options(p.parse_args(["--rtol", "1e-7"]), "fit").compiled_method
    'rodas4'
    """
    base = SolverOptions.preset(purpose)
    g = parser.add_argument_group(
        "solver", f"time integration; defaults are the '{purpose}' preset of "
        "liquidamp.options.PRESETS, the library's own default (a flag changes that value only)")
    g.add_argument("--rtol", type=float, default=None, metavar="RTOL",
                   help=f"relative tolerance [-], {RTOL_RANGE[0]:g} to {RTOL_RANGE[1]:g} "
                        f"(default {base.rtol:g})")
    aliases = ", ".join(f"{a} = {c}" for a, c in ENGINE_ALIASES.items())
    g.add_argument("--engine", choices=ENGINES + tuple(ENGINE_ALIASES), default=None,
                   help=f"integration engine: scipy (solve_ivp, the reference) or compiled "
                        f"(numba core) (default {base.engine}; alias {aliases})")
    g.add_argument("--compiled-method", choices=COMPILED_METHODS, default=None,
                   help="stepper of the compiled engine: auto (Dormand-Prince, RODAS4 where "
                        f"stiff), rodas4 or dopri5 (default {base.compiled_method})")


def solver_options(args, purpose: str = "default") -> SolverOptions | None:
    """Options from the solver flags: None without any (the library's default preset).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of a command that called :func:`add_solver_arguments`.
    purpose : str
        The preset the flags modify (the same as given to
        :func:`add_solver_arguments`).

    Returns
    -------
    SolverOptions or None
        ``None`` when no flag was given; otherwise the preset with the
        given values.

    Raises
    ------
    ParameterError
        A value outside its allowed range, e.g. ``--rtol 2``; the message
        (from :class:`~liquidamp.options.SolverOptions`) names the option, the
        value and the range, and the command exits with 2; also
        ``--compiled-method`` with an engine other than ``compiled``.

    Examples
    --------
    >>> import argparse
    >>> solver_options(argparse.Namespace(rtol=None, engine=None, compiled_method=None))
    >>> solver_options(argparse.Namespace(rtol=None, engine="python",
    ...                                   compiled_method=None)).engine
    'scipy'
    >>> solver_options(argparse.Namespace(rtol=2.0, engine=None, compiled_method=None))
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: rtol must lie in [1e-14, 0.01] [-], got 2
    """
    base = SolverOptions.preset(purpose)  # an unknown purpose raises, listing the presets
    changes = {k: getattr(args, k) for k in SOLVER_FLAGS if getattr(args, k, None) is not None}
    if not changes:
        return None
    options = base.replace(**changes)
    if "compiled_method" in changes and options.engine != "compiled":
        raise ParameterError(f"--compiled-method {options.compiled_method} chooses the stepper "
                             f"of the compiled engine, but the engine is {options.engine!r}; "
                             "add --engine compiled")
    return options
