"""Field-dependent effects: a valve whose fluid yields under a controlled field (issue #20).

Part of the catalogue of :mod:`liquidamp.device.effects` (the public face: the table, the
composition order, :func:`~liquidamp.device.effects.with_effects`); the
:class:`~liquidamp.device.effects_base.Effect` base, which documents how an effect reads a
measured input channel, is in :mod:`liquidamp.device.effects_base`.

References
----------
.. [1] B. F. Spencer Jr., S. J. Dyke, M. K. Sain, J. D. Carlson, "Phenomenological model for
   magnetorheological dampers", J. Eng. Mech. 123(3), 1997 (the first-order lag of the field
   behind the command, du/dt = -eta (u - v)).
.. [2] N. M. Wereley, L. Pang, G. M. Kamath, "Idealized hysteresis modeling of
   electrorheological and magnetorheological dampers", J. Intell. Mater. Syst. Struct. 9(8),
   1998 (Bingham plastic valve: yield pressure drop plus viscous loss).
.. [3] B. Titurus, AIAA J. 56(10), 2018, eq. (10) (the channel's momentum balance).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.effects_base import Effect
from liquidamp.errors import ParameterError, check_nonnegative, check_positive

#: Bases whose channel has a mass-flow state the yield drop acts on (its momentum balance).
FIELD_YIELD_BASES = ("full", "inertial", "inertial_2state")

#: Control inputs a field yield may follow.
FIELD_INPUTS = ("voltage", "current")


@dataclass(frozen=True)
class FieldYield(Effect):
    """Field-dependent yield in the channel (MR or ER valve), driven by a measured input.

    The channel's pressure balance (eq. 10 of [3]_) gains a Bingham-like yield pressure
    drop [2]_, smoothed at zero flow,

        S_t dm12/dt = p1 - p2 - g1 m12 - g2 m12 |m12| - dp_y(u_f) tanh(m12 / m_eps),
        dp_y(u_f) = dp_y0 + dp_y1 |u_f|,

    where the field u_f follows the measured control input u (the record's ``voltage`` or
    ``current`` channel, chosen by ``input``) through a first-order lag [1]_

        du_f/dt = eta (u - u_f)          (state ``u_field`` [V or A]).

    Below yield (|dp| < dp_y) the flow is held to about m_eps: the fluid's compliance
    then gives the pre-yield stiffness and hysteresis of MR dampers without a separate
    Bouc-Wen state.  ``inertial_2state`` reads the volumetric flow (m12 = rho0 q, over
    L_t); the reductions without channel inertia refuse it (their loss relation would
    need an implicit solve).  Zero yield (dp_y0 = dp_y1 = 0) gives the passive device
    exactly, whatever the input; a field-independent yield is dp_y1 = 0.  The rigid-fluid
    limit under steady flow at piston speed v: F = A_p (dp_y tanh(m/m_eps) + g1 m +
    g2 m|m|), m = rho0 A_p v.  It reads a measured channel, so it runs only where one
    drives it (a record: :func:`~liquidamp.analysis.measured.record_model.simulate_record`);
    an analytic stroke, a coupled host and the frequency-domain analyses refuse it naming
    why.  The field starts settled on the input's first value (:meth:`input_state`).  Its
    Jacobian is analytic (with the base's, where the other effects keep it analytic).

    Parameters
    ----------
    yield_pressure_Pa : float
        dp_y0 >= 0, yield pressure drop at zero field [Pa].
    yield_pressure_per_input : float
        dp_y1 >= 0, yield pressure drop per unit field [Pa/V or Pa/A].
    lag_rate_per_s : float
        eta > 0, rate of the field's first-order lag [1/s] (time constant 1/eta).
    smoothing_flow_kg_per_s : float
        m_eps > 0, mass flow over which the yield drop changes sign [kg/s].
    input : {"voltage", "current"}
        The measured channel the field follows (a composition field).

    Examples
    --------
    >>> from liquidamp.device.models import get_model
    >>> from liquidamp.device.effects import with_effects
    >>> e = FieldYield(6e4, 2.2e5, 120.0, 5e-4)
    >>> e.input_channels, e.input
    (('voltage',), 'voltage')
    >>> m = with_effects(get_model("full"), e)
    >>> m.state_names[5:], m.input_channels
    (('u_field',), ('voltage',))
    >>> with_effects(get_model("no_inertia"), e)
    Traceback (most recent call last):
    ...
    liquidamp.errors.ParameterError: effect 'field_yield' acts on the channel's momentum \
balance (a mass-flow state); model 'no_inertia' has none; use 'full', 'inertial', \
'inertial_2state'
    """

    yield_pressure_Pa: float = 0.0
    yield_pressure_per_input: float = 0.0
    lag_rate_per_s: float = 100.0
    smoothing_flow_kg_per_s: float = 1e-3
    input: str = dataclasses.field(default="voltage",
                                   metadata={"composition": FIELD_INPUTS})
    name: ClassVar[str] = "field_yield"
    units: ClassVar[dict] = {"yield_pressure_Pa": "Pa", "yield_pressure_per_input": "Pa/V",
                             "lag_rate_per_s": "1/s", "smoothing_flow_kg_per_s": "kg/s"}
    fit_keys: ClassVar[tuple] = ("yield_pressure_Pa", "yield_pressure_per_input",
                                 "lag_rate_per_s")
    bounds: ClassVar[dict] = {"yield_pressure_Pa": (1.0, 1e8),
                              "yield_pressure_per_input": (1.0, 1e8),
                              "lag_rate_per_s": (1.0, 1e4),
                              "smoothing_flow_kg_per_s": (1e-7, 1.0)}
    order: ClassVar[int] = 6
    description: ClassVar[str] = ("field-dependent yield of an MR/ER channel following a "
                                  "measured voltage or current through a first-order lag")
    state_names: ClassVar[tuple] = ("u_field",)
    state_units: ClassVar[tuple] = ("V",)
    slot: ClassVar[int] = K.S_FY
    kind: ClassVar[str] = "fluid"
    small_signal_reason: ClassVar[str | None] = (
        "it follows a measured input channel, which a linearization at rest does not have")
    describing_reason: ClassVar[str | None] = (
        "it follows a measured input channel (voltage or current), which a frequency-domain "
        "analysis does not have")

    def __post_init__(self):
        check_nonnegative("field_yield yield_pressure_Pa", self.yield_pressure_Pa, "Pa")
        check_nonnegative("field_yield yield_pressure_per_input",
                          self.yield_pressure_per_input, "Pa/V or Pa/A")
        check_positive("field_yield lag_rate_per_s", self.lag_rate_per_s, "1/s")
        check_positive("field_yield smoothing_flow_kg_per_s", self.smoothing_flow_kg_per_s,
                       "kg/s")
        self._check_composition()

    @property
    def input_channels(self) -> tuple[str, ...]:  # type: ignore[override]
        """The measured channel the field follows: ``(input,)``."""
        return (self.input,)

    def check_small_signal(self, params) -> None:
        """Always refused: the field follows a measured input a linearization has not."""
        raise ParameterError(
            f"effect {self.name!r} has no small-signal model and no equivalent "
            f"linearization: {self.small_signal_reason}; drive it with a record that has a "
            f"{self.input} column (liquidamp.analysis.measured.record_model.simulate_record)")

    def check(self, model):
        if model.base not in FIELD_YIELD_BASES:
            raise ParameterError(
                f"effect {self.name!r} acts on the channel's momentum balance (a mass-flow "
                f"state); model {model.name!r} has none; use "
                f"{', '.join(map(repr, FIELD_YIELD_BASES))}")

    def pack(self, ep):
        ep[K.E_DPY0] = self.yield_pressure_Pa
        ep[K.E_DPY1] = self.yield_pressure_per_input
        ep[K.E_ETA] = self.lag_rate_per_s
        ep[K.E_MEPS] = self.smoothing_flow_kg_per_s
        ep[K.E_FYCH] = float(K.channel_index(self.input))

    def input_state(self, params, y0, inputs):
        """The field settled on the input's first value: u_f(0) = u(0)."""
        return np.array([float(inputs.get(self.input, 0.0))])

    def state_scales(self, params):
        return np.array([1.0])

    def yield_pressure(self, field):
        """dp_y = dp_y0 + dp_y1 |u_f| at the field ``field`` [Pa] (vectorized)."""
        return self.yield_pressure_Pa + self.yield_pressure_per_input * np.abs(field)

    @classmethod
    def probe(cls, force_amplitude_N, amplitude, omega, params):
        """Yield drops of 5 % of the force amplitude at zero field and per unit field over
        the piston area, the field lag at the record's frequency, m_eps at 1 % of the
        record's peak mass flow."""
        dp = 0.05 * force_amplitude_N / params.A_p
        m_peak = params.rho0 * params.A_p * amplitude * omega
        return cls(dp, dp, max(10.0 * omega, 10.0), max(0.01 * m_peak, 1e-6))
