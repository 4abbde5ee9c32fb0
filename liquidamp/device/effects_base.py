"""The :class:`Effect` base of the add-on effects and the helpers every family shares.

The catalogue, its composition rules and :func:`~liquidamp.device.effects.with_effects`
are described in :mod:`liquidamp.device.effects` (the public face, which re-exports
every name); the effects themselves are in the family modules
:mod:`~liquidamp.device.effects_force`, :mod:`~liquidamp.device.effects_kinematic`,
:mod:`~liquidamp.device.effects_fluid` and :mod:`~liquidamp.device.effects_operating`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device.models import DeviceModel, check_input_channels  # noqa: F401 (API)
from liquidamp.errors import (
    ParameterError,
    check_choice,
    check_finite,
)

# ---------------------------------------------------------------------------
# effect classes

#: Field metadata key of a composition field (a choice of where the effect sits; not a
#: fitted parameter): the allowed values.
_COMPOSITION = "composition"

#: Where a friction effect sits: on the rod (the measured stroke), or at the piston
#: behind the kinematic effects (in series with a dead band, like the fluid).
LOCATIONS = ("rod", "piston")


def _location_field():
    return dataclasses.field(default="rod", metadata={_COMPOSITION: LOCATIONS})


#: Allowed reverse-to-forward level ratio of a direction-dependent friction [-].
REVERSE_RATIO_BOUNDS = (0.1, 10.0)


def _check_reverse_ratio(effect) -> None:
    q = check_finite(f"{effect.name} reverse_ratio", effect.reverse_ratio, "-")
    lo, hi = REVERSE_RATIO_BOUNDS
    if not lo <= q <= hi:
        raise ParameterError(f"{effect.name} reverse_ratio must be in [{lo:g}, {hi:g}] [-] "
                             f"(reverse-to-forward friction level), got {q:g}")


def _check_location(effect, effects) -> None:
    if effect.location != "piston":
        return
    if any(e.name == "series_compliance" for e in effects):
        raise ParameterError(
            f"effect {effect.name!r} at location 'piston' cannot sit behind "
            "series_compliance: a massless piston between a spring and dry friction is a "
            "stick-slip element without a rate while it sticks; put the friction at "
            "location 'rod' or drop series_compliance")


@dataclass(frozen=True)
class Effect:
    """Base class of the add-on effects.

    Class attributes (metadata): ``name`` (registry key), ``units``
    (parameter key -> unit), ``fit_keys`` (parameters a calibration varies by
    default), ``bounds`` (key -> (low, high) for fitting), ``needs_pressures``
    (only for models with chamber pressure states), ``order`` (canonical
    composition rank), ``state_names`` / ``state_units`` (states the effect
    appends), ``slot`` (where the compiled composition records it:
    a ``liquidamp.device.kernels.S_*`` index), ``kind`` (``"force"``: adds
    to the load-cell force only, driven by the measured stroke;
    ``"kinematic"``: sits between the measured stroke and the piston;
    ``"fluid"``: acts on the chamber equations).

    Measured inputs (issue #20): ``input_channels`` names the measured channels the
    effect reads, from :data:`liquidamp.device.kernels.CHANNELS` (``"temperature"``
    [K], ``"voltage"`` [V], ``"current"`` [A], ``"pressure"`` [Pa]; a class attribute,
    or a property where a composition field chooses it).  The composed model reads
    their union (:func:`input_channels`, :attr:`DeviceModel.input_channels`).  The
    compiled law reads channel ``k = kernels.channel_index(name)`` at the current time
    as ``prm[P_CH + k]`` (SI) and its time derivative as ``prm[P_CHD + k]``; the driver
    writes both at every Runge-Kutta stage from the channel series carried by the
    stroke (:class:`~liquidamp.structure.testmachine.RecordedStroke` ``channels``, on
    the stroke's time grid, interpolated linearly as the stroke is, on both engines;
    :func:`liquidamp.analysis.measured.record_model.simulate_record` passes a record's
    channels).  A drive without the series a model reads is refused before any work,
    naming the effect, the channel and the channels there are
    (:func:`check_input_channels`): the test machine under an analytic stroke
    (``simulate``, ``steady_state``), the coupled hosts, and the frequency-domain
    analyses (no describing function, no small-signal model).  On the scipy engine the
    values travel as a fourth entry of ``u = (y, v, a, c)``, ``c`` the
    :data:`~liquidamp.device.kernels.N_CH` channel values (or their rows over samples)
    in slot order.  An effect whose states follow an input starts settled on the input's
    first value where it states how (:meth:`input_state`, used by
    :func:`initial_state_with_inputs`).
    """

    name: ClassVar[str] = ""
    units: ClassVar[dict] = {}
    fit_keys: ClassVar[tuple] = ()
    bounds: ClassVar[dict] = {}
    needs_pressures: ClassVar[bool] = False
    order: ClassVar[int] = 0
    description: ClassVar[str] = ""
    state_names: ClassVar[tuple] = ()
    state_units: ClassVar[tuple] = ()
    slot: ClassVar[int] = -1
    kind: ClassVar[str] = "force"
    uses_acceleration: ClassVar[bool] = False
    #: True where the effect's force is linear (affine) in the stroke: its describing
    #: function is then its exact element at any amplitude, also at rest.
    linear: ClassVar[bool] = False
    #: True where a diagnosis screens the effect when no candidates are named; the
    #: others are candidates on request (``diagnose(..., candidates=...)``).
    screened: ClassVar[bool] = True
    #: False for an effect that drifts by design (``self_heating``): it has no periodic
    #: steady state, so a record with it is marched whole and never averaged into a cycle.
    stationary: ClassVar[bool] = True
    #: Measured channels the effect reads (names of ``kernels.CHANNELS``; see above).
    input_channels: ClassVar[tuple] = ()
    #: Value of a parameter at which the effect adds nothing to the bare model, where that
    #: is not 0 (a symmetric rebound ratio 1, a rigid series spring ``math.inf``): the
    #: point from which a diagnosis's score test measures the effect's strength.
    bare: ClassVar[dict] = {}

    @classmethod
    def parameter_keys(cls) -> tuple[str, ...]:
        """Keys of the numeric (fittable) parameters, SI.

        Examples
        --------
        >>> from liquidamp.device.effects import CoulombFriction
        >>> CoulombFriction.parameter_keys(), CoulombFriction.composition_keys()
        (('force_N', 'reverse_ratio'), {'location': ('rod', 'piston')})
        """
        return tuple(f.name for f in dataclasses.fields(cls) if _COMPOSITION not in f.metadata)

    @classmethod
    def composition_keys(cls) -> dict[str, tuple[str, ...]]:
        """Composition fields (key -> allowed values): where the effect sits, never fitted."""
        return {f.name: f.metadata[_COMPOSITION] for f in dataclasses.fields(cls)
                if _COMPOSITION in f.metadata}

    @property
    def parameters(self) -> dict[str, float]:
        """Numeric parameter values by key (SI): what a fit may vary."""
        return {k: getattr(self, k) for k in self.parameter_keys()}

    @property
    def composition(self) -> dict[str, str]:
        """Composition choices by key (e.g. ``location``): part of the model, not fitted."""
        return {k: getattr(self, k) for k in self.composition_keys()}

    def as_dict(self) -> dict:
        """Parameters and composition choices: what rebuilds the effect (device files, JSON).

        Examples
        --------
        >>> from liquidamp.device.effects import make_effect
        >>> e = make_effect("coulomb_friction", force_N=100.0, location="piston")
        >>> e.as_dict()
        {'force_N': 100.0, 'reverse_ratio': 1.0, 'location': 'piston'}
        >>> str(e)
        'coulomb_friction(force_N=100, reverse_ratio=1, location=piston)'
        >>> make_effect(**{"name": "coulomb_friction", **e.as_dict()}) == e
        True
        """
        return {**self.parameters, **self.composition}

    def replace(self, **changes) -> Effect:
        """Validated copy with ``changes`` applied; unknown keys raise ParameterError."""
        for key in changes:
            check_choice(f"{self.name} parameter", key, self.as_dict())
        return dataclasses.replace(self, **changes)

    def _check_composition(self) -> None:
        for key, allowed in self.composition_keys().items():
            value = getattr(self, key)
            if value not in allowed:
                raise ParameterError(f"{self.name} {key} must be one of "
                                     f"{', '.join(map(repr, allowed))}, got {value!r}")

    @classmethod
    def probe(cls, force_amplitude_N: float, amplitude: float, omega: float, params
              ) -> Effect:
        """The effect at a small probe strength for a record (the diagnosis's score test).

        Parameters
        ----------
        force_amplitude_N : float
            Amplitude of the measured force [N].
        amplitude, omega : float
            Stroke amplitude [m] and angular frequency [rad/s] of the records.
        params : DeviceParams or ViscousParams
            The calibrated parameters.

        Raises
        ------
        ParameterError
            For an effect that states no probe.
        """
        raise ParameterError(f"no probe for effect {cls.name!r}")

    def spec_flags(self) -> dict[int, int]:
        """Extra composition slots (``kernels.S_*`` -> value) beyond :attr:`slot`."""
        return {}

    def check_with(self, effects: tuple) -> None:
        """Raise ParameterError if the effect cannot be composed with the other ``effects``."""

    def pack(self, ep: np.ndarray) -> None:  # pragma: no cover - abstract
        """Write the parameters into their slots of the compiled effect vector ``ep``."""
        raise NotImplementedError

    def check(self, model: DeviceModel) -> None:
        """Raise ParameterError if the effect cannot be composed with ``model``."""
        if self.needs_pressures and "p1" not in model.state_names[:model.n_base_states]:
            raise ParameterError(
                f"effect {self.name!r} needs a model with chamber pressure states p1, p2; "
                f"model {model.name!r} has states ({', '.join(model.state_names) or 'none'}); "
                "use 'full', 'no_inertia', 'constant_bulk', 'volumetric' or 'inertial'")

    #: Why the effect has no small-signal model at rest (None: the linearization of the
    #: composed equations at rest holds it exactly).
    small_signal_reason: ClassVar[str | None] = None
    #: Why the effect has no describing function in parallel with the fluid (None: it has).
    describing_reason: ClassVar[str | None] = (
        "it changes the fluid equations, so its first harmonic is not a force in parallel "
        "with the fluid's")

    def check_small_signal(self, params) -> None:
        """Raise ParameterError if the linearization at rest cannot represent the effect."""
        if self.small_signal_reason is not None:
            hint = ("give an amplitude and a frequency for an equivalent linearization, or "
                    "use the time domain" if self.stationary else
                    "it drifts with the power it dissipates, so no amplitude-independent "
                    "linearization holds it either: use the time domain (simulate, or the "
                    "nonlinear points of stiffness: its periodic steady state is the "
                    "thermal equilibrium)")
            raise ParameterError(
                f"effect {self.name!r} has no small-signal model at rest: "
                f"{self.small_signal_reason}; {hint}")

    def describing_function(self, amplitude: float, omega: float, params, model=None
                            ) -> tuple[float, float, float]:
        """Equivalent parallel element of the effect at y = Y sin(w t) (first harmonic).

        Parameters
        ----------
        amplitude : float
            Stroke amplitude Y > 0 [m].
        omega : float
            Angular frequency w > 0 [rad/s].
        params : DeviceParams or ViscousParams
            Device parameters.
        model : DeviceModel, optional
            The composed model (effects whose first harmonic depends on the
            base equation need it).

        Returns
        -------
        (k, c, b) : tuple of float
            Stiffness [N/m], damping [N s/m] and inertance [kg] in parallel
            with the fluid force whose first harmonic equals the effect's:
            its dynamic stiffness is k + i w c - w^2 b.

        Raises
        ------
        ParameterError
            Where the effect does not act as a force in parallel (naming why).
        """
        raise ParameterError(
            f"effect {self.name!r} has no equivalent linearization in parallel with the "
            f"fluid: {self.describing_reason}; use the time domain "
            "(liquidamp.analysis.response.stiffness.nonlinear_stiffness)")

    def initial_state(self, params, y0: float) -> np.ndarray:
        """Initial values of the effect's states at rest with rod stroke ``y0`` [m]."""
        return np.zeros(len(self.state_names))

    def input_state(self, params, y0: float, inputs: dict) -> np.ndarray:
        """Initial values of the effect's states at rest with the measured channels at the
        start, ``inputs`` (name -> value, SI) (default: :meth:`initial_state`); e.g. a
        field lag starts settled on the first input (:func:`initial_state_with_inputs`)."""
        return self.initial_state(params, y0)

    def rest_base_state(self, model: DeviceModel, params, y0: float,
                        x_base: np.ndarray) -> np.ndarray:
        """The base model's states at rest with the effect (default: ``x_base`` unchanged).

        ``model`` is the bare base model, ``x_base`` its rest state at rod
        stroke ``y0`` [m] as the effects before this one left it.
        """
        return x_base

    def state_scales(self, params) -> np.ndarray:
        """Magnitudes of the effect's states (tolerances, difference increments)."""
        return np.ones(len(self.state_names))

    def __str__(self) -> str:
        pars = [f"{k}={v:.4g}" for k, v in self.parameters.items()]
        pars += [f"{k}={v}" for k, v in self.composition.items()]
        return f"{self.name}({', '.join(pars)})"



def input_channels(effects) -> tuple[str, ...]:
    """The measured channels a set of effects reads, in slot order (``kernels.CHANNELS``).

    Examples
    --------
    >>> from liquidamp.device.effects import CoulombFriction
    >>> input_channels((CoulombFriction(30.0),))
    ()
    """
    from liquidamp.device.kernels_layout import CHANNELS

    wanted = {c for e in effects for c in e.input_channels}
    return tuple(c for c in CHANNELS if c in wanted)


def initial_state_with_inputs(model, params, y0: float, inputs: dict) -> np.ndarray:
    """``model.initial_state(params, y0)`` with the states of the effects that read measured
    channels set by :meth:`Effect.input_state` from the channels at the start, ``inputs``
    (name -> value, SI).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> initial_state_with_inputs(get_model("full"), preset("reference"), 0.0, {}).size
    5
    """
    x = np.array(model.initial_state(params, y0), float)
    i = model.n_base_states
    for e in model.effects:
        k = len(e.state_names)
        if e.input_channels and k:
            x[i:i + k] = e.input_state(params, y0, inputs)
        i += k
    return x


def _shaped(value, *inputs):
    """A float where every input is scalar, else the array."""
    if all(np.ndim(q) == 0 for q in inputs):
        return float(value)
    return value


def _check_harmonic(amplitude, omega) -> tuple[float, float]:
    Y, w = float(amplitude), float(omega)
    if not (math.isfinite(Y) and Y > 0):
        raise ParameterError(f"amplitude must be finite and > 0 [m], got {amplitude!r}")
    if not (math.isfinite(w) and w > 0):
        raise ParameterError(f"omega must be finite and > 0 [rad/s], got {omega!r}")
    return Y, w



def piston_stroke_index(model_effects, n_base: int):
    """Index of the state that holds the piston's stroke, or None where the piston is the rod.

    Behind a kinematic effect (``series_compliance``, ``freeplay``'s dead band with the
    fluid behind it) the piston has a state of its own [m]; the innermost such effect's.

    Parameters
    ----------
    model_effects : sequence of Effect
        A composed model's effects, in its state order.
    n_base : int
        Number of the base model's states (the effects' states follow them).

    Returns
    -------
    int or None

    Examples
    --------
    >>> from liquidamp.device.effects import Freeplay
    >>> piston_stroke_index((Freeplay(1e-4),), 5), piston_stroke_index((), 5)
    (5, None)
    """
    i = n_base
    index = {}
    for e in model_effects:
        index[e.name] = i
        i += len(e.state_names)
    behind = {e.name: getattr(e, "fluid_behind", True) for e in model_effects}
    for name in ("series_compliance", "freeplay"):
        if name in index and behind[name]:
            return index[name]
    return None
