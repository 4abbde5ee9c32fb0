"""Solver options: every tolerance that can change an answer, in one place.

:class:`SolverOptions` is frozen and validated; unknown options raise.  The
defaults are tight enough for the stiff, non-smooth device (checked by the
convergence tests in ``tests/coupled``).

Every function that integrates takes ``options: SolverOptions | None = None``
and resolves ``None`` through :func:`resolve_options` to one of the named
:data:`PRESETS`; there are no other per-function defaults.  The command line
builds its options from the same presets (``liquidamp.commands._solver``), so
a command and the library function it calls integrate alike unless
``--rtol``, ``--engine`` or ``--compiled-method`` say otherwise.

=========  ======  =====  ==========  ========  =======  =====================================
preset     method  rtol   atol_scale  engine    stepper  used by (``options=None``)
=========  ======  =====  ==========  ========  =======  =====================================
default    Radau   1e-8   1e-9        compiled  auto     testrig ``simulate``/``steady_state``,
                                                         ``simulate_record``, periodic orbit,
                                                         stiffness sweeps,
                                                         equivalent linearization
coupled    Radau   1e-8   1e-9        scipy     auto     ``simulate_coupled`` (any host)
fit        Radau   1e-6   1e-8        compiled  rodas4   ``calibrate``, ``predict``,
                                                         ``diagnose``
rotor      DOP853  1e-7   1e-9        compiled  auto     ``fast_rotor.simulate_rotor``,
                                                         ``simulate_lco``
section    Radau   1e-6   1e-9        scipy     auto     ``simulate_section_lco``
casestudy  Radau   1e-8   1e-9        compiled  auto     ``run_case_study`` (``liquidamp demo``)
decay      DOP853  1e-10  1e-12       compiled  auto     ``fast_rotor.second_order_flow``, forced
                                                         orbits and lag decays
                                                         (``analysis.stability.forced_lag``)
=========  ======  =====  ==========  ========  =======  =====================================

(``engine`` of ``default`` is :data:`DEFAULT_ENGINE`; the stepper is
``compiled_method``, used by the compiled engine only.  Every preset allows the compiled
kernels' 5 000 000 steps per span or period (``max_steps``) but ``fit``, which allows
:data:`FIT_MAX_STEPS` per period of a record.)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from numbers import Integral
from types import MappingProxyType

from liquidamp.errors import ParameterError, check_choice, check_in_range, check_positive

__all__ = ["SolverOptions", "DEFAULT_OPTIONS", "DEFAULT_ENGINE", "ENGINES", "ENGINE_ALIASES",
           "COMPILED_METHODS", "PRESETS", "FIT_MAX_STEPS", "RTOL_RANGE", "preset_names",
           "resolve_options"]

_METHODS = ("Radau", "BDF", "LSODA", "RK45", "DOP853")
#: Allowed relative tolerance [-]: below 1e-14 is round-off, above 1e-2 no answer.
RTOL_RANGE = (1e-14, 1e-2)
#: Steppers of the compiled engine (see ``SolverOptions.compiled_method``).
COMPILED_METHODS = ("auto", "rodas4", "dopri5")
#: Integration engines: the reference, scipy ``solve_ivp`` on the models' Python
#: right-hand sides, and the numba-compiled core of :mod:`liquidamp.coupled.fast`.
ENGINES = ("scipy", "compiled")
#: Former engine names, accepted and normalised to the canonical one
#: (``"python"`` was the scipy engine's name before issue #11).
ENGINE_ALIASES = MappingProxyType({"python": "scipy"})
#: The engine used when none is named, by the library (``SolverOptions()``, the
#: ``default`` preset) and the command line alike.  ``"scipy"`` until the
#: compiled engine runs every model, effect and host; then ``"compiled"``.
DEFAULT_ENGINE = "compiled"


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances and limits of the time integration and the periodic steady state.

    Parameters
    ----------
    method : str
        :func:`scipy.integrate.solve_ivp` method; an implicit one
        (``Radau``, ``BDF``, ``LSODA``) for the stiff device.  Used by the
        ``"scipy"`` engine only.
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
    engine : {"scipy", "compiled"}
        Default :data:`DEFAULT_ENGINE`.
        ``"scipy"``: scipy :func:`~scipy.integrate.solve_ivp` with the
        models' Python right-hand sides (the reference); ``"python"`` is
        accepted as an alias and stored as ``"scipy"``.  ``"compiled"``: the
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
    max_steps : int
        Most integrator steps of one span, or of one period of a periodic march, on the
        compiled engine [-] (default 5 000 000, the compiled kernels' own limit); past it
        the run stops with :class:`~liquidamp.errors.ConvergenceError` naming the
        figure.  The ``fit`` preset sets a budget that its model runs reach only where a
        parameter point makes the model far stiffer than the records can show (see
        :data:`PRESETS`), so a fit is not held up by one such point.  The scipy engine
        has no step count and does not use it.

    Examples
    --------
    >>> SolverOptions(rtol=1e-6).rtol
    1e-06
    >>> SolverOptions(engine="python").engine
    'scipy'
    >>> SolverOptions.preset("fit").rtol
    1e-06
    >>> SolverOptions.from_mapping({"rtl": 1e-6})
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown solver option 'rtl'; valid: method, rtol, \
atol_scale, samples_per_period, steady_tol, min_cycles, max_cycles, pressure_floor, \
vapour_pressure, max_step_fraction, engine, compiled_method, max_steps
    >>> SolverOptions(engine="fortran")
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: unknown engine 'fortran'; valid: scipy, compiled \
(alias: python = scipy)
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
    engine: str = DEFAULT_ENGINE
    compiled_method: str = "auto"
    max_steps: int = 5_000_000

    def __post_init__(self) -> None:
        if isinstance(self.engine, str) and self.engine in ENGINE_ALIASES:
            object.__setattr__(self, "engine", ENGINE_ALIASES[self.engine])
        if self.engine not in ENGINES:
            aliases = ", ".join(f"{a} = {c}" for a, c in ENGINE_ALIASES.items())
            raise ParameterError(f"unknown engine {self.engine!r}; valid: {', '.join(ENGINES)} "
                                 f"(alias: {aliases})")
        check_choice("solver method", self.method, _METHODS)
        check_in_range("rtol", self.rtol, *RTOL_RANGE)
        check_in_range("atol_scale", self.atol_scale, 1e-16, 1e-2)
        check_in_range("samples_per_period", self.samples_per_period, 16, 1 << 16)
        check_in_range("steady_tol", self.steady_tol, 1e-12, 1e-1)
        check_in_range("min_cycles", self.min_cycles, 1, 10_000)
        check_in_range("max_cycles", self.max_cycles, self.min_cycles, 100_000)
        check_positive("pressure_floor", self.pressure_floor, "Pa")
        check_positive("vapour_pressure", self.vapour_pressure, "Pa")
        check_in_range("max_step_fraction", self.max_step_fraction, 1e-6, 1.0)
        check_choice("compiled method", self.compiled_method, COMPILED_METHODS)
        if isinstance(self.max_steps, bool) or not isinstance(self.max_steps, Integral):
            raise ParameterError(f"max_steps must be an integer number of integrator steps "
                                 f"[-], got {self.max_steps!r}")
        check_in_range("max_steps", self.max_steps, 100, 1 << 40)

    @classmethod
    def from_mapping(cls, values: Mapping) -> SolverOptions:
        """Build options from a mapping; unknown keys raise ParameterError."""
        _check_keys(values)
        return cls(**values)

    @classmethod
    def preset(cls, name: str, **changes) -> SolverOptions:
        """The named preset of :data:`PRESETS`, with validated ``changes``.

        Examples
        --------
        >>> SolverOptions.preset("rotor").method
        'DOP853'
        >>> SolverOptions.preset("fit", rtol=1e-7).compiled_method
        'rodas4'
        >>> SolverOptions.preset("fitting")
        Traceback (most recent call last):
        ...
        liquidamp.errors.ParameterError: unknown solver preset 'fitting'; valid: default, coupled, \
fit, rotor, section, casestudy, decay
        """
        base = PRESETS[check_choice("solver preset", name, PRESETS)]
        return base.replace(**changes) if changes else base

    def over_periods(self, periods: float) -> SolverOptions:
        """These options for one run over ``periods`` periods of its stroke [-]: the step
        limit :attr:`max_steps`, which holds per period of a periodic march, times the
        periods (at least one).

        Examples
        --------
        >>> SolverOptions(max_steps=1000).over_periods(20.0).max_steps
        20000
        >>> SolverOptions(max_steps=1000).over_periods(0.2).max_steps
        1000
        """
        n = max(1.0, float(periods)) if math.isfinite(periods) else 1.0
        return self.replace(max_steps=int(min(self.max_steps * n, 1 << 40)))

    def replace(self, **changes) -> SolverOptions:
        """Validated copy with ``changes`` applied; unknown keys raise ParameterError.

        Examples
        --------
        >>> SolverOptions().replace(rtl=1e-6)
        Traceback (most recent call last):
        ...
        liquidamp.errors.ParameterError: unknown solver option 'rtl'; valid: method, rtol, \
atol_scale, samples_per_period, steady_tol, min_cycles, max_cycles, pressure_floor, \
vapour_pressure, max_step_fraction, engine, compiled_method, max_steps
        """
        _check_keys(changes)
        return dataclasses.replace(self, **changes)


def _check_keys(values: Mapping) -> None:
    names = [f.name for f in dataclasses.fields(SolverOptions)]
    for key in values:
        check_choice("solver option", key, names)


#: ``max_steps`` of the ``fit`` preset: integrator steps per period of a record simulation
#: [-].  Measured (session 17, ``runs/s17_lead``) over the default diagnoses of every shared
#: record (60 560 periodic compiled runs): median 215 steps per period, 99.9 % below 3 901,
#: the most 23 598 (a candidate refit with end stops, freeplay and friction contacts).  The
#: runs past it are parameter points the records cannot tell from their neighbours, made
#: stiff beyond what the stepper resolves cheaply: a floating freeplay's contact at 4e10 N/m
#: (4e4 x the records' stiffness, on the friction start's small fluid) took 339 000 steps a
#: period (889 at 4e9 N/m), 6 s a period, and the diagnosis of the strong set's R_mass20
#: 257 s (47 s with this budget, the same result).  Past the budget the run fails and the
#: fit steps back, as from any failed run.
FIT_MAX_STEPS = 100_000

PRESETS: Mapping[str, SolverOptions] = MappingProxyType({
    # The device on the test machine (simulate, steady_state, simulate_record, shooting):
    # tight enough for the stiff, non-smooth device (the convergence tests in tests/coupled
    # hold |K*| at this rtol), on DEFAULT_ENGINE: the compiled engine runs every model of
    # the family with any effects (one copy of the physics) and agrees with scipy's Radau
    # to ~1e-7 in |K*| (tests/coupled/test_engines.py).
    "default": SolverOptions(),
    # A device inside any host (simulate_coupled): scipy, the engine that runs every host;
    # the compiled kernel covers only the rotor built by rotor_system ("rotor" preset,
    # simulate_rotor / simulate_lco), and there is no silent fall-back between engines.
    "coupled": SolverOptions(engine="scipy"),
    # Least-squares fitting: finite-difference Jacobians of the residual need a smooth,
    # cheap model run rather than the reference's accuracy; rtol 1e-6 keeps the run error
    # well under record noise.  Compiled engine (numba is a dependency; simulate_record
    # runs the effects the compiled kernels lack on scipy's LSODA) with RODAS4 throughout:
    # its smaller global error at rtol 1e-6 keeps the Jacobians clean; with Dormand-Prince
    # the demo diagnosis took 13x longer and added freeplay and leakage (commit b8618ad).
    "fit": SolverOptions(rtol=1e-6, atol_scale=1e-8, engine="compiled",
                         compiled_method="rodas4", max_steps=FIT_MAX_STEPS),
    # Rotor + devices in the time domain (limit cycles): the coupled Hammond system is not
    # stiff for the device presets, so the explicit DOP853 at rtol 1e-7 (growth rates and
    # amplitudes to ~1e-5).  Compiled rotor kernel: the same DOP853 (scipy's coefficients
    # and step control), agreeing with scipy's to ~1e-13; simulate_lco runs scipy's DOP853
    # where compiled_support() says the kernel cannot run the system.
    "rotor": SolverOptions(method="DOP853", rtol=1e-7, engine="compiled"),
    # Typical section + device (flutter limit cycles): Radau for the stiff device, rtol 1e-6
    # for runs of many mode periods; scipy engine, the compiled one has no section host.
    "section": SolverOptions(rtol=1e-6, engine="scipy"),
    # The paper's case study (Figs. 7-11, `liquidamp demo`): the default tolerances on the
    # compiled engine, which integrates everything the study runs (the full model under
    # harmonic strokes) and agrees with scipy's Radau to ~1e-7 in |K*| (tests/coupled/
    # test_fast.py); on scipy the study takes ~20x longer (111 s against ~5 s).
    "casestudy": SolverOptions(engine="compiled"),
    # Forced periodic orbits and free decays on top of them (the lag damping under 1/rev
    # forcing, analysis.stability.forced_lag): the orbit is found by Newton to ~1e-10 and
    # the decay signal is the difference of two runs a thousandth of the orbit apart, so
    # the runs must be accurate to far below that; DOP853 on the compiled second-order
    # kernel (blade and rotor hosts).  The quadratic loss's kink at zero flow limits the
    # step (error ~ h^3 there), not the order: rtol 1e-10 costs ~300 steps per revolution.
    "decay": SolverOptions(method="DOP853", rtol=1e-10, atol_scale=1e-12, engine="compiled"),
})
"""Named solver presets (module docstring table); ``SolverOptions.preset(name)``."""

DEFAULT_OPTIONS = PRESETS["default"]


def preset_names() -> tuple[str, ...]:
    """Names of the solver presets.

    Examples
    --------
    >>> preset_names()
    ('default', 'coupled', 'fit', 'rotor', 'section', 'casestudy', 'decay')
    """
    return tuple(PRESETS)


def resolve_options(options: SolverOptions | None, purpose: str = "default") -> SolverOptions:
    """The options a function integrates with: ``options``, or the preset ``purpose``.

    The one place where a function's default solver options are chosen.

    Parameters
    ----------
    options : SolverOptions or None
        The caller's options, used as given; ``None`` selects the preset.
    purpose : str
        Name of the preset in :data:`PRESETS` the calling function documents.

    Returns
    -------
    SolverOptions

    Raises
    ------
    ParameterError
        ``options`` is neither None nor a SolverOptions, or ``purpose`` is
        not a preset name.

    Examples
    --------
    >>> resolve_options(None, "section").rtol
    1e-06
    >>> resolve_options(SolverOptions(rtol=1e-5), "fit").rtol
    1e-05
    >>> resolve_options({"rtol": 1e-5})
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: options must be a SolverOptions or None, got dict; \
use SolverOptions.from_mapping or SolverOptions.preset(name, **changes)
    """
    if options is None:
        return SolverOptions.preset(purpose)
    check_choice("solver preset", purpose, PRESETS)
    if not isinstance(options, SolverOptions):
        raise ParameterError(
            f"options must be a SolverOptions or None, got {type(options).__name__}; use "
            "SolverOptions.from_mapping or SolverOptions.preset(name, **changes)")
    return options
