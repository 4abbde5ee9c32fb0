"""Realistic synthetic test-machine records: a known model, effects, noise and distortion.

:func:`synthetic_record` runs a device model (any variant, with any
catalogue effect from :mod:`liquidamp.device.effects`) under a test-machine
stroke that is not quite a sine (small 2nd and 3rd harmonics, as a real
servo-hydraulic actuator delivers), settles it to its periodic steady state,
then samples it the way the paper's rig did (Sec. IV.B: 200 Hz, LVDT stroke,
load cell), starting mid-cycle, with LVDT and load-cell noise and an LVDT
zero offset.  The model is driven by the exact stroke; the record holds only
noisy samples, so a reader must differentiate it as for measured data.

A recipe with a ``band`` drives the model with a broadband stroke instead
(:class:`BroadbandStroke`: a random-phase multisine, flat from the band's lower
edge to its upper edge), as for a random-excitation test of an MR damper.

Every record carries its recipe in ``Record.meta`` (``recipe_dict``), so the
bundled files in ``liquidamp/analysis/measured/data`` are documented and
reproducible (see the README there).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Sec. IV.B.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from liquidamp.analysis.measured.record_model import integrate
from liquidamp.analysis.measured.records import Record, write_record
from liquidamp.device import preset as get_preset
from liquidamp.device.effects import (
    Effect,
    chambers_on_absolute_stroke,
    make_effect,
    on_absolute_stroke,
    with_effects,
)
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_in_range, check_nonnegative, check_positive

__all__ = ["DistortedStroke", "BroadbandStroke", "Recipe", "synthetic_record",
           "recipe_from_dict", "write_synthetic"]


@dataclass(frozen=True)
class DistortedStroke:
    """y = Y [sin(w t + phi) + d2 sin(2 w t + phi2) + d3 sin(3 w t + phi3)] [m].

    Callable ``t -> (y, v, a)`` for scalar t (plain floats).
    """

    amplitude: float
    frequency: float
    phase: float = 0.0
    d2: float = 0.0
    d3: float = 0.0
    phase2: float = 0.0
    phase3: float = 0.0

    @property
    def period(self) -> float:
        """Period [s]."""
        return 1.0 / self.frequency

    @property
    def max_abs(self) -> float:
        """Bound on |y| [m]."""
        return self.amplitude * (1.0 + abs(self.d2) + abs(self.d3))

    def __call__(self, t):
        w = 2.0 * math.pi * self.frequency
        Y = self.amplitude
        y = v = a = 0.0
        for k, d, ph in ((1, 1.0, self.phase), (2, self.d2, self.phase2),
                         (3, self.d3, self.phase3)):
            if d == 0.0:
                continue
            arg = k * w * t + ph
            s, c = math.sin(arg), math.cos(arg)
            y += Y * d * s
            v += Y * d * k * w * c
            a -= Y * d * (k * w) ** 2 * s
        return y, v, a

    def arrays(self, t):
        """(y, v, a) at an array of times."""
        out = np.array([self(float(tt)) for tt in np.asarray(t, float)])
        return out[:, 0], out[:, 1], out[:, 2]


@dataclass(frozen=True)
class BroadbandStroke:
    """A random-phase multisine y = sum_k A sin(2 pi k f0 t + phi_k) [m], k f0 in the band.

    Components at every multiple k f0 of the lower band edge f0 up to the upper
    edge, of equal amplitude A = rms sqrt(2 / n) (n components), phases
    ``phases``: a flat, broadband stroke of RMS ``rms`` that repeats only
    every 1/f0 [s].  Callable ``t -> (y, v, a)`` for scalar t.

    Examples
    --------
    >>> s = BroadbandStroke(rms=3e-4, band=(0.5, 20.0), phases=tuple(range(40)))
    >>> t = np.arange(0, 2.0, 1e-3)
    >>> y, _, _ = s.arrays(t)
    >>> len(s.phases), round(float(np.sqrt(np.mean(y * y))) * 1e3, 1)
    (40, 0.3)
    """

    rms: float
    band: tuple
    phases: tuple

    def __post_init__(self):
        lo, hi = (float(b) for b in self.band)
        check_positive("band lower edge", lo, "Hz")
        if not hi > lo:
            raise ParameterError(f"band must rise: got {lo:g} to {hi:g} Hz")
        if len(self.phases) != int(math.floor(hi / lo + 1e-9)):
            raise ParameterError(f"BroadbandStroke needs {int(math.floor(hi / lo + 1e-9))} "
                                 f"phases for the band {lo:g}-{hi:g} Hz, got "
                                 f"{len(self.phases)}")

    @property
    def frequencies(self) -> np.ndarray:
        """Component frequencies [Hz]."""
        return self.band[0] * np.arange(1, len(self.phases) + 1)

    @property
    def period(self) -> float:
        """Repeat period 1/f0 [s]."""
        return 1.0 / self.band[0]

    @property
    def max_abs(self) -> float:
        """Largest |y| over one repeat period (a 64-point-per-component grid) [m]."""
        t = np.linspace(0.0, self.period, 64 * len(self.phases) + 1)
        return float(np.max(np.abs(self.arrays(t)[0])))

    def __call__(self, t):
        y, v, a = self.arrays(np.array([float(t)]))
        return float(y[0]), float(v[0]), float(a[0])

    def arrays(self, t):
        """(y, v, a) at an array of times."""
        t = np.asarray(t, float)
        w = 2 * math.pi * self.frequencies
        A = self.rms * math.sqrt(2.0 / len(self.phases))
        arg = np.outer(t, w) + np.asarray(self.phases, float)
        s, c = np.sin(arg), np.cos(arg)
        return A * s.sum(axis=1), A * (c * w).sum(axis=1), -A * (s * w * w).sum(axis=1)


@dataclass(frozen=True)
class Recipe:
    """Everything that makes a synthetic record (SI; frequency in Hz).

    Attributes
    ----------
    preset : str
        Device preset (``liquidamp.device.preset``).
    model : str
        Device model name.
    effects : tuple of (name, parameters) pairs
        Catalogue effects included in the truth.
    frequency : float
        Excitation frequency [Hz].
    amplitude : float
        Stroke amplitude [m].
    sampling_rate : float
        Samples per second [Hz] (paper: 200).
    cycles : float
        Cycles recorded [-].
    start_phase : float or None
        Phase of the fundamental at the first sample [rad]; None: drawn from the seed.
    distortion : (float, float)
        2nd and 3rd harmonic of the stroke relative to the fundamental [-].
    displacement_noise : float
        LVDT noise standard deviation [m].
    force_noise : float
        Load-cell noise standard deviation [N].
    displacement_offset : float
        LVDT zero offset [m]: the device runs about its own zero and the record reads the
        stroke plus this offset; for a gas-charged device with chambers it is the absolute
        mean stroke instead (the record's zero is the stroke datum, V01 and V02 are held
        there: :func:`~liquidamp.device.effects.on_absolute_stroke`, as the fit reads it).
    seed : int
        Random seed (noise, harmonic phases, start phase).
    multipliers : tuple of (name, value) pairs
        Multipliers applied to the preset (DeviceParams.scaled).
    band : tuple
        ``()`` (default): the distorted sine above.  ``(f_lo, f_hi)`` [Hz]: a
        broadband stroke (:class:`BroadbandStroke`) of RMS amplitude / sqrt(2)
        instead; the record then lasts ``cycles / frequency`` [s] and
        ``distortion`` is not used.
    """

    preset: str = "paper_calibrated"
    model: str = "full"
    effects: tuple = ()
    frequency: float = 3.0
    amplitude: float = 0.003
    sampling_rate: float = 200.0
    cycles: float = 8.0
    start_phase: float | None = None
    distortion: tuple = (0.01, 0.005)
    displacement_noise: float = 2.0e-6
    force_noise: float = 1.0
    displacement_offset: float = 0.0
    seed: int = 0
    multipliers: tuple = field(default=())
    band: tuple = ()

    def __post_init__(self):
        check_positive("frequency", self.frequency, "Hz")
        check_positive("amplitude", self.amplitude, "m")
        check_in_range("sampling_rate", self.sampling_rate, 10 * self.frequency, 1e6, "Hz")
        check_in_range("cycles", self.cycles, 1.0, 1e4)
        check_nonnegative("displacement_noise", self.displacement_noise, "m")
        check_nonnegative("force_noise", self.force_noise, "N")
        if len(self.distortion) != 2:
            raise ParameterError("distortion must hold the 2nd and 3rd harmonic fractions")
        if self.band:
            if len(self.band) != 2 or not 0 < self.band[0] < self.band[1]:
                raise ParameterError(f"band must be (f_lo, f_hi) with 0 < f_lo < f_hi [Hz], got "
                                     f"{self.band!r}")
            check_in_range("sampling_rate", self.sampling_rate, 10 * self.band[1], 1e6, "Hz")

    def params(self) -> DeviceParams:
        """Device parameters of the truth."""
        p = get_preset(self.preset)
        return p.scaled(**dict(self.multipliers)) if self.multipliers else p

    def effect_objects(self) -> tuple[Effect, ...]:
        """The truth's effects as Effect objects."""
        return tuple(make_effect(n, **dict(kv)) for n, kv in self.effects)

    def as_dict(self) -> dict:
        """JSON-ready recipe."""
        return {
            "synthetic": True, "preset": self.preset, "model": self.model,
            "multipliers": dict(self.multipliers),
            "effects": {n: dict(kv) for n, kv in self.effects},
            "frequency [Hz]": self.frequency, "amplitude [m]": self.amplitude,
            "sampling_rate [Hz]": self.sampling_rate, "cycles": self.cycles,
            "start_phase [rad]": self.start_phase, "distortion [-]": list(self.distortion),
            "displacement_noise [m]": self.displacement_noise,
            "force_noise [N]": self.force_noise,
            "displacement_offset [m]": self.displacement_offset, "seed": self.seed,
            **({"band [Hz]": list(self.band)} if self.band else {}),
        }


def recipe_from_dict(d: dict) -> Recipe:
    """Inverse of :meth:`Recipe.as_dict`."""
    return Recipe(
        preset=d["preset"], model=d["model"],
        multipliers=tuple(sorted(d.get("multipliers", {}).items())),
        effects=tuple((n, tuple(sorted(kv.items()))) for n, kv in d.get("effects", {}).items()),
        frequency=d["frequency [Hz]"], amplitude=d["amplitude [m]"],
        sampling_rate=d["sampling_rate [Hz]"], cycles=d["cycles"],
        start_phase=d["start_phase [rad]"], distortion=tuple(d["distortion [-]"]),
        displacement_noise=d["displacement_noise [m]"], force_noise=d["force_noise [N]"],
        displacement_offset=d["displacement_offset [m]"], seed=d["seed"],
        band=tuple(d.get("band [Hz]", ())))


def _orbit_start(model, params, stroke, rest):
    """State at t = 0 of the periodic orbit under ``stroke`` (a DistortedStroke), or
    ``rest`` where none is found (the record then settles from rest)."""
    from liquidamp.coupled.testrig import steady_state
    from liquidamp.errors import LiquidampError
    from liquidamp.structure.testmachine import FourierStroke

    Y = stroke.amplitude
    coeff = [(1.0, stroke.phase), (stroke.d2, stroke.phase2), (stroke.d3, stroke.phase3)]
    sine = [Y * d * math.cos(ph) for d, ph in coeff]
    cosine = [Y * d * math.sin(ph) for d, ph in coeff]
    try:
        orbit = steady_state(model, params, FourierStroke(stroke.frequency, sine, cosine),
                             x0=rest)
    except LiquidampError:
        return rest
    return np.array(orbit.states[:, 0])


def synthetic_record(recipe: Recipe | None = None, *, settle_cycles: int = 6,
                     rtol: float = 1e-8, window: int = 21, order: int = 4,
                     **changes) -> Record:
    """Generate a record from ``recipe`` (keyword ``changes`` build or alter one).

    ``effects`` may be given as a dict {name: {key: value}} or Effect objects
    in ``changes``.  A periodic stroke's record starts on the truth model's
    periodic steady state: the orbit's state (:func:`liquidamp.coupled.testrig.steady_state`
    under the stroke's Fourier series; rest where none is found) starts
    ``settle_cycles`` LSODA periods before sampling starts at ``start_phase``, so that a
    slowly settling device (air-free chambers, cavities) holds no start-up transient that
    a model on its own periodic orbit could not reproduce; a broadband stroke settles
    from rest.

    Examples
    --------
    >>> r = synthetic_record(frequency=4.0, amplitude=0.002, cycles=3, seed=1,
    ...                      effects={"coulomb_friction": {"force_N": 30.0}})
    >>> round(r.frequency, 2), round(r.amplitude * 1e3, 2), r.meta["recipe"]["synthetic"]
    (4.0, 2.0, True)
    """
    if "effects" in changes:
        eff = changes["effects"]
        if isinstance(eff, dict):
            eff = tuple((n, tuple(sorted(kv.items()))) for n, kv in eff.items())
        else:
            eff = tuple((e.name, tuple(sorted(e.as_dict().items()))) if isinstance(e, Effect)
                        else e for e in eff)
        changes["effects"] = eff
    if "multipliers" in changes and isinstance(changes["multipliers"], dict):
        changes["multipliers"] = tuple(sorted(changes["multipliers"].items()))
    recipe = Recipe(**changes) if recipe is None else (
        Recipe(**{**recipe.__dict__, **changes}) if changes else recipe)
    rng = np.random.default_rng(recipe.seed)
    ph2, ph3, ph0 = rng.uniform(-math.pi, math.pi, 3)
    phase = recipe.start_phase if recipe.start_phase is not None else float(ph0)
    d2, d3 = recipe.distortion
    if recipe.band:
        n_comp = int(math.floor(recipe.band[1] / recipe.band[0] + 1e-9))
        stroke = BroadbandStroke(recipe.amplitude / math.sqrt(2.0), tuple(recipe.band),
                                 tuple(rng.uniform(-math.pi, math.pi, n_comp)))
    else:
        stroke = DistortedStroke(recipe.amplitude, recipe.frequency, phase, d2, d3, ph2, ph3)
    params = recipe.params()
    model = with_effects(get_model(recipe.model), *recipe.effect_objects())
    model.check_params(params)
    # a gas-charged device with chambers runs on the absolute stroke, as the fit simulates it
    # (simulate_record): chambers V01, V02 at the datum, the record about its offset (other
    # position effects keep the offset as an LVDT zero error: the device about its own zero)
    if chambers_on_absolute_stroke(model):
        model, params = on_absolute_stroke(model, params, recipe.displacement_offset)
    if stroke.max_abs >= params.stroke_limit:
        raise ParameterError(f"stroke {stroke.max_abs:.4g} m reaches the chamber end "
                             f"{params.stroke_limit:.4g} m")
    T = stroke.period
    n = int(round(recipe.cycles / recipe.frequency * recipe.sampling_rate)) + 1
    t = np.arange(n) / recipe.sampling_rate
    # settle: march from rest over whole cycles ending at t = 0 (stroke is periodic)
    t_settle = np.linspace(-settle_cycles * T, 0.0, settle_cycles * 16 + 1)
    hmax = T / 200.0 if not recipe.band else 1.0 / (50.0 * recipe.band[1])
    x0 = model.initial_state(params, stroke(-settle_cycles * T)[0])
    if model.n_states and not recipe.band:
        x0 = _orbit_start(model, params, stroke, x0)
    if model.n_states:
        Xs = integrate(model, params, stroke, t_settle, x0, rtol=rtol, atol_scale=1e-10,
                       hmax=hmax)
        X = integrate(model, params, stroke, t, Xs[:, -1], rtol=rtol, atol_scale=1e-10,
                      hmax=hmax)
    else:
        X = np.zeros((0, n))
    y, v, a = stroke.arrays(t)
    force = np.asarray(model.force(t, X, (y, v, a), params), float) * np.ones(n)
    y_meas = y + recipe.displacement_offset + rng.normal(0.0, recipe.displacement_noise, n)
    f_meas = force + rng.normal(0.0, recipe.force_noise, n)
    t_meas = t + 1.0  # the machine clock does not start at zero
    h = window // 2  # Record drops the one-sided filter ends
    meta = {"recipe": recipe.as_dict(), "true_force": force[h:n - h],
            "true_effects": {e.name: e.as_dict() for e in recipe.effect_objects()}}
    return Record.from_arrays(t_meas, y_meas, f_meas, window=window, order=order,
                              source="", meta=meta)


def write_synthetic(path, recipe: Recipe | None = None, **changes) -> Path:
    """Generate a record, write it as CSV and its recipe as a JSON sidecar (same stem)."""
    rec = synthetic_record(recipe, **changes)
    path = Path(path)
    write_record(path, rec)
    side = path.with_suffix(".json")
    from liquidamp.atomic import write_text

    write_text(side, json.dumps(rec.meta["recipe"], indent=2) + "\n")
    return path
