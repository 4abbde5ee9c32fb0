"""Solver options: every tolerance that can change an answer, in one place.

:class:`SolverOptions` is frozen and validated; unknown options raise.  The
defaults are tight enough for the stiff, non-smooth device (checked by the
convergence tests in ``tests/coupled``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from liquidamp.errors import ParameterError, check_choice, check_in_range, check_positive

__all__ = ["SolverOptions", "DEFAULT_OPTIONS", "ENGINES", "COMPILED_METHODS"]

_METHODS = ("Radau", "BDF", "LSODA", "RK45", "DOP853")
#: Steppers of the compiled engine (see ``SolverOptions.compiled_method``).
COMPILED_METHODS = ("auto", "rodas4", "dopri5")
#: Integration engines: the plain-Python reference (scipy ``solve_ivp``) and the
#: numba-compiled core of :mod:`liquidamp.coupled.fast`.
ENGINES = ("python", "compiled")


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances and limits of the time integration and the periodic steady state.

    Parameters
    ----------
    method : str
        :func:`scipy.integrate.solve_ivp` method; an implicit one
        (``Radau``, ``BDF``, ``LSODA``) for the stiff device.  Used by the
        ``"python"`` engine only.
    rtol : float
        Relative tolerance [-].
    atol_scale : float
        Absolute tolerance of each state as a fraction of the model's state
        scale (``DeviceModel.state_scales``) [-].
    samples_per_period : int
        Output samples per excitation period (first-harmonic extraction and
        plots) [-].
    steady_tol : float
        The periodic steady state is accepted when the estimated remaining
        change of the force waveform, relative to its peak, is below this [-].
    min_cycles, max_cycles : int
        Bounds on the number of excitation cycles marched.
    pressure_floor : float
        A chamber pressure at or below this stops the run with
        :class:`~liquidamp.errors.PressureError` [Pa].
    vapour_pressure : float
        Pressure under which the result carries a cavitation warning
        (water at 20 C: 2339 Pa) [Pa].
    max_step_fraction : float
        Largest integration step as a fraction of the excitation period [-].
    engine : {"python", "compiled"}
        ``"python"``: scipy :func:`~scipy.integrate.solve_ivp` with the
        models' Python right-hand sides (the reference).  ``"compiled"``: the
        numba-compiled core of :mod:`liquidamp.coupled.fast`, with the
        same ``rtol``, ``atol_scale`` and largest step, and much faster;
        it supports the models listed in
        :data:`liquidamp.coupled.fast.COMPILED_MODELS` and raises
        ParameterError for others.  It serves the test machine
        (:mod:`liquidamp.coupled.testrig`, stepper ``compiled_method``) and
        :func:`liquidamp.coupled.assembly.simulate_coupled` for a rotor built by
        ``rotor_system`` with compiled device models (always DOP853 there:
        ``method`` is ignored).
    compiled_method : {"auto", "rodas4", "dopri5"}
        Stepper of the ``"compiled"`` engine.  ``"auto"`` (default): the
        explicit Dormand-Prince 5(4) pair while the problem is not stiff,
        switching to the L-stable Rosenbrock method RODAS4 when Hairer's
        stiffness test fires (h |lambda| > 3.25 on 15 accepted steps; in the
        periodic steady state the test restarts each period), as LSODA
        switches from Adams to BDF; ``"rodas4"``: RODAS4 throughout;
        ``"dopri5"``: Dormand-Prince throughout (no switch; slow, not wrong,
        on stiff problems).  Every choice controls the same error norm.

    Examples
    --------
    >>> SolverOptions(rtol=1e-6).rtol
    1e-06
    >>> SolverOptions.from_mapping({"rtl": 1e-6})
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown solver option 'rtl'; valid: method, rtol, \
atol_scale, samples_per_period, steady_tol, min_cycles, max_cycles, pressure_floor, \
vapour_pressure, max_step_fraction, engine, compiled_method
    >>> SolverOptions(engine="fortran")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown engine 'fortran'; valid: python, compiled
    """

    method: str = "Radau"
    rtol: float = 1e-8
    atol_scale: float = 1e-9
    samples_per_period: int = 512
    steady_tol: float = 1e-6
    min_cycles: int = 3
    max_cycles: int = 400
    pressure_floor: float = 1.0
    vapour_pressure: float = 2339.0
    max_step_fraction: float = 0.02
    engine: str = "python"
    compiled_method: str = "auto"

    def __post_init__(self) -> None:
        check_choice("solver method", self.method, _METHODS)
        check_in_range("rtol", self.rtol, 1e-14, 1e-2)
        check_in_range("atol_scale", self.atol_scale, 1e-16, 1e-2)
        check_in_range("samples_per_period", self.samples_per_period, 16, 1 << 16)
        check_in_range("steady_tol", self.steady_tol, 1e-12, 1e-1)
        check_in_range("min_cycles", self.min_cycles, 1, 10_000)
        check_in_range("max_cycles", self.max_cycles, self.min_cycles, 100_000)
        check_positive("pressure_floor", self.pressure_floor, "Pa")
        check_positive("vapour_pressure", self.vapour_pressure, "Pa")
        check_in_range("max_step_fraction", self.max_step_fraction, 1e-6, 1.0)
        check_choice("engine", self.engine, ENGINES)
        check_choice("compiled method", self.compiled_method, COMPILED_METHODS)

    @classmethod
    def from_mapping(cls, values: dict) -> SolverOptions:
        """Build options from a mapping; unknown keys raise ParameterError."""
        names = [f.name for f in dataclasses.fields(cls)]
        for key in values:
            check_choice("solver option", key, names)
        return cls(**values)

    def replace(self, **changes) -> SolverOptions:
        """Validated copy with ``changes`` applied."""
        try:
            return dataclasses.replace(self, **changes)
        except TypeError as exc:
            raise ParameterError(str(exc)) from None


DEFAULT_OPTIONS = SolverOptions()
