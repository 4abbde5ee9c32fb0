"""Linear views of the device: transfer functions and state-space linearization.

Every transfer function here maps the stroke Y(s) [m] to the load-cell force
F(s) [N], K(s) = F(s)/Y(s), and is a :class:`control.TransferFunction` with
input ``'stroke'`` and output ``'force'``.  On the imaginary axis K(i omega)
is the dynamic stiffness of :mod:`liquidamp.analysis.response.harmonics` (sine
convention: phase 0 deg spring, 90 deg damper, 180 deg inerter).

Closed forms
------------
Maxwell unit, eq. (16) linear (laminar loss only, no inertia)::

    K_M(s) = k_D T_D s / (T_D s + 1),   k_D = A_p^2 B,  T_D = c1 / B

Dashpot plus inerter, eq. (19) (incompressible liquid, laminar loss)::

    K_DI(s) = c_L s + b_L s^2,          c_L = c1 A_p^2,  b_L = L_t A_p^2

This is improper: a ``TransferFunction`` holds it (frequency response,
products with proper host TFs), a ``StateSpace`` cannot.  For
interconnection, :func:`linearize` gives it as a static map from stroke rate
and acceleration, F = c_L v + b_L a (the host supplies both).

Inertial two-state model, eq. (18) linearized (c2 -> 0, the slope of the
quadratic loss at zero flow), with B = B1/V01 + B2/V02 [Pa/m^3] and the
channel inertance L_t = rho_l S_t [kg/m^4]::

    s dP = B (A_p s Y - Q)                      (chamber compliance)
    L_t s Q = dP - c1 Q                          (channel)
    => Q = dP / (L_t s + c1)
    => dP [s (L_t s + c1) + B] = B A_p s Y (L_t s + c1)
    => K(s) = A_p dP / Y = A_p^2 B s (L_t s + c1) / (L_t s^2 + c1 s + B)

and the channel flow per stroke Q/Y = A_p B s / (L_t s^2 + c1 s + B).
Limits, each exact at every frequency (tested):

* B -> inf (incompressible):  K -> A_p^2 (L_t s^2 + c1 s) = eq. (19);
* L_t -> 0 (no inertance):     K -> A_p^2 B c1 s / (c1 s + B) = Maxwell with
  k_D = A_p^2 B, T_D = c1 / B;
* c1 -> 0 (no resistance):     K -> A_p^2 B L_t s^2 / (L_t s^2 + B), i.e.
  1/K = 1/k_D + 1/(b_L s^2): a spring k_D in series with an inerter b_L;
* c1 -> inf (closed channel):  K -> A_p^2 B = k_D, a spring.

State-space linearization
-------------------------
:func:`linearize` linearizes any registered model about an operating point
(default: rest at p0).  The models take u = (y, v, a), so the linearization
keeps the three inputs ``('stroke', 'stroke_rate', 'stroke_acceleration')``
[m, m/s, m/s^2] -- the same signals as :func:`liquidamp.analysis.response.iosys.to_iosys`
and therefore comparable with ``control.linearize`` -- and outputs
``'force'`` [N] plus ``'p1'``, ``'p2'`` [Pa] where the model has chamber
pressures (deviations from the operating point).  The stroke-only view is
derived from it, consistently, by the state shift z = x - b_v y, exact
because no model's state equation depends on the acceleration::

    x' = A x + b_y y + b_v y'   =>   z' = A z + (A b_v + b_y) y
    F  = C x + d_y y            =>   F  = C z + (C b_v + d_y) y

which gives a proper StateSpace from the stroke alone
(:meth:`Linearization.stroke_system`) and K(s) = C (sI - A)^-1 (b_y + s b_v)
+ d_y + s d_v + s^2 d_a for every model (:meth:`Linearization.frequency_response`,
:meth:`Linearization.transfer_function`; the algebraic models give their
improper polynomial).

Coulomb friction (|F_f| sign v) has no small-signal linearization; it is left
out here (the fluid force only) and enters the equivalent linearization of
:mod:`liquidamp.analysis.response.equivalent` through its describing function.

The full model (eq. 10) linearized at rest has the invariants of the sealed
device (total mass; each chamber's density a function of its pressure), so
its A has eigenvalues at 0 that are uncontrollable from the stroke and
unobservable in the force.  :meth:`Linearization.minimal` removes them; its
stroke-to-force transfer function equals the one of eq. (18) with B at p0 and
the linear loss c1 (the quadratic loss has zero slope at rest).

References
----------
.. [1] B. Titurus, "Generalized Liquid-Based Damping Device for Passive
   Vibration Control", AIAA J. 56(10), 4134-4145, 2018, eqs. (10), (16),
   (18), (19), (20).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np

from liquidamp._compat import renamed
from liquidamp.device.models import DeviceModel, get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError, check_finite, check_positive

__all__ = [
    "INPUT_NAMES",
    "Linearization",
    "linearize",
    "maxwell_tf",
    "dashpot_inerter_tf",
    "inertial_2state_tf",
    "inertial_2state_coefficients",
    "flow_tf",
    "transfer_function",
    "tf_frequency_response",
    "CLOSED_FORM_MODELS",
]

#: Input signals of a linearization and of :func:`liquidamp.analysis.response.iosys.to_iosys`.
INPUT_NAMES = ("stroke", "stroke_rate", "stroke_acceleration")

#: Models whose stroke-to-force transfer function has a closed form here.
CLOSED_FORM_MODELS = ("maxwell", "dashpot", "spring", "dashpot_inerter", "inerter",
                      "inertial_2state")


def _tf(num, den, name: str) -> control.TransferFunction:
    return control.tf(list(map(float, num)), list(map(float, den)), inputs="stroke",
                      outputs="force", name=name)


def _check_params(params) -> DeviceParams:
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    return params


# ---------------------------------------------------------------------------
# closed-form transfer functions


def maxwell_tf(params: DeviceParams) -> control.TransferFunction:
    """Maxwell unit of eq. (16), K(s) = k_D T_D s / (T_D s + 1) [N/m].

    Parameters
    ----------
    params : DeviceParams
        Needs c1 > 0 [kg m^-4 s^-1]; uses k_D [N/m] and T_D [s] (bulk moduli at p0).

    Returns
    -------
    control.TransferFunction
        Input ``'stroke'`` [m], output ``'force'`` [N].

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> K = maxwell_tf(p)
    >>> w = 1.0 / p.T_D      # corner: |K| = k_D / sqrt(2), phase 45 deg
    >>> k = complex(K(1j * w))
    >>> round(abs(k) / p.k_D * 2**0.5, 12), round(math.degrees(math.atan2(k.imag, k.real)), 9)
    (1.0, 45.0)
    """
    p = _check_params(params)
    get_model("maxwell").check_params(p)
    return _tf([p.k_D * p.T_D, 0.0], [p.T_D, 1.0], "maxwell")


def dashpot_inerter_tf(params: DeviceParams) -> control.TransferFunction:
    """Dashpot and inerter in parallel, eq. (19): K(s) = b_L s^2 + c_L s [N/m].

    Improper (numerator of higher degree than the denominator): fine for the
    frequency response and for products with strictly proper host transfer
    functions, but it has no StateSpace.  For interconnection use
    ``linearize("dashpot_inerter", params).system`` (a static map from
    stroke rate and acceleration, the host supplying both).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> k = complex(dashpot_inerter_tf(p)(2j * math.pi))   # 1 Hz
    >>> bool(np.isclose(k.real, -p.b_L * (2 * math.pi) ** 2)), bool(np.isclose(k.imag, p.c_L
    ... * 2 * math.pi))
    (True, True)
    """
    p = _check_params(params)
    return _tf([p.b_L, p.c_L, 0.0], [1.0], "dashpot_inerter")


def inertial_2state_coefficients(params: DeviceParams, *, B: float | None = None,
                                 c1: float | None = None, L_t: float | None = None) -> dict:
    """Coefficients of the linear eq. (18): A_p [m^2], B [Pa/m^3], L_t [kg/m^4], c1.

    ``B`` defaults to B1(p0)/V01 + B2(p0)/V02, ``c1`` [kg m^-4 s^-1] to
    ``params.c1``, ``L_t`` to rho_l S_t; overrides must be finite and >= 0
    (B > 0).
    """
    p = _check_params(params)
    B = p.B_eff if B is None else check_positive("B", B, "Pa/m^3")
    c1 = p.c1 if c1 is None else check_finite("c1", c1, "kg m^-4 s^-1")
    L_t = p.L_t if L_t is None else check_finite("L_t", L_t, "kg/m^4")
    if c1 < 0 or L_t < 0:
        raise ParameterError(f"c1 and L_t must be >= 0, got c1 = {c1:g}, L_t = {L_t:g}")
    if c1 == 0 and L_t == 0:
        raise ParameterError("c1 and L_t are both 0: the channel has no impedance")
    return {"A_p": p.A_p, "B": B, "L_t": L_t, "c1": c1}


def inertial_2state_tf(params: DeviceParams, *, B: float | None = None,
                       c1: float | None = None, L_t: float | None = None
                       ) -> control.TransferFunction:
    """Linear eq. (18): K(s) = A_p^2 B s (L_t s + c1) / (L_t s^2 + c1 s + B) [N/m].

    Derivation and limits in the module docstring.  The quadratic loss c2 is
    dropped (zero slope at rest); for finite amplitudes see
    :func:`liquidamp.analysis.response.equivalent.equivalent_transfer_function`.

    Parameters
    ----------
    params : DeviceParams
        Device.
    B : float, optional
        Stiffness factor B1/V01 + B2/V02 [Pa/m^3] (default at p0).
    c1 : float, optional
        Linear (or equivalent) loss [kg m^-4 s^-1] (default ``params.c1``).
    L_t : float, optional
        Channel inertance [kg/m^4] (default rho_l S_t).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> K = inertial_2state_tf(p)
    >>> round(float(K(0.0).real), 9)              # no static stiffness: the channel equalizes
    0.0
    >>> k = complex(K(1e7j))                       # high frequency: the compliance, k_D
    >>> round(abs(k) / p.k_D, 4)
    1.0
    """
    c = inertial_2state_coefficients(params, B=B, c1=c1, L_t=L_t)
    A2B = c["A_p"] ** 2 * c["B"]
    return _tf([A2B * c["L_t"], A2B * c["c1"], 0.0], [c["L_t"], c["c1"], c["B"]],
               "inertial_2state")


def flow_tf(params: DeviceParams, *, B: float | None = None, c1: float | None = None,
            L_t: float | None = None) -> control.TransferFunction:
    """Channel flow per stroke of linear eq. (18): Q/Y = A_p B s / (L_t s^2 + c1 s + B).

    Units [m^3/s per m]; input ``'stroke'``, output ``'q12'``.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> w = 1e-3                                  # slow: all displaced liquid flows
    >>> round(abs(complex(flow_tf(p)(1j * w))) / (p.A_p * w), 6)
    1.0
    """
    c = inertial_2state_coefficients(params, B=B, c1=c1, L_t=L_t)
    return control.tf([c["A_p"] * c["B"], 0.0], [c["L_t"], c["c1"], c["B"]], inputs="stroke",
                      outputs="q12", name="flow")


def transfer_function(model: str | DeviceModel, params: DeviceParams
                      ) -> control.TransferFunction:
    """Stroke-to-force transfer function of any registered model at rest.

    Closed forms for ``maxwell`` (eq. 16), ``dashpot``, ``spring``,
    ``dashpot_inerter`` (eq. 19), ``inerter`` (eq. 20) and
    ``inertial_2state`` (eq. 18); every other model through
    ``linearize(model, params).transfer_function()``.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("reference")
    >>> K_full = transfer_function("full", p)
    >>> K_18 = transfer_function("inertial_2state", p)
    >>> s = 2j * math.pi * 7.0
    >>> abs(complex(K_full(s)) / complex(K_18(s)) - 1) < 1e-9
    True
    """
    m = get_model(model)
    p = _check_params(params)
    m.check_params(p)
    if m.name == "maxwell":
        return maxwell_tf(p)
    if m.name == "dashpot":
        return _tf([p.c_L, 0.0], [1.0], "dashpot")
    if m.name == "spring":
        return _tf([p.k_D], [1.0], "spring")
    if m.name == "dashpot_inerter":
        return dashpot_inerter_tf(p)
    if m.name == "inerter":
        return _tf([p.b_L, 0.0, 0.0], [1.0], "inerter")
    if m.name == "inertial_2state":
        return inertial_2state_tf(p)
    return linearize(m, p).transfer_function()


def tf_frequency_response(tf, frequencies_hz) -> np.ndarray:
    """Complex K(i 2 pi f) of a SISO transfer function or LTI system [its unit].

    Evaluates numerator and denominator polynomials directly (works for
    improper TFs as well).
    """
    f = np.atleast_1d(np.asarray(frequencies_hz, float))
    s = 2j * math.pi * f
    if isinstance(tf, control.TransferFunction):
        num = np.asarray(tf.num[0][0], float)
        den = np.asarray(tf.den[0][0], float)
        return np.polyval(num, s) / np.polyval(den, s)
    return np.array([complex(np.squeeze(tf(si))) for si in s])


# ---------------------------------------------------------------------------
# linearization


def _rel_steps(scales: np.ndarray) -> np.ndarray:
    return np.cbrt(np.finfo(float).eps) * np.where(scales > 0, scales, 1.0)


def _central(fun, x0: np.ndarray, j: int, h: float) -> np.ndarray:
    """d fun / d x_j by central differences with one Richardson step.

    The quadratic loss q|q| (and its inverse) has a kink in its slope at zero
    flow, where a plain central difference errs by a term linear in h; the
    combination 2 D(h/2) - D(h) cancels it and leaves O(h^2).
    """

    def d(step):
        e = np.zeros_like(x0)
        e[j] = step
        return (np.asarray(fun(x0 + e), float) - np.asarray(fun(x0 - e), float)) / (2 * step)

    return 2.0 * d(0.5 * h) - d(h)


def _outputs(model: DeviceModel, params, x, u) -> np.ndarray:
    out = [float(model.fluid_force(0.0, x, u, params))]
    if model.pressures is not None:
        p1, p2 = model.pressures(x, u, params)
        out += [float(p1), float(p2)]
    return np.array(out)


def _output_names(model: DeviceModel) -> tuple[str, ...]:
    return ("force", "p1", "p2") if model.pressures is not None else ("force",)


def _u_steps(params: DeviceParams) -> np.ndarray:
    # the models are affine in v and a, and smooth in y: steps need no tuning
    return np.array([1e-6 * params.stroke_limit, 1e-4, 1e-2])


@dataclass(frozen=True, eq=False)
class Linearization:
    """Linearization of a device model about an operating point (x0, u0).

    delta x' = A delta x + B delta u, delta out = C delta x + D delta u with
    u = (stroke [m], stroke_rate [m/s], stroke_acceleration [m/s^2]) and out
    = (force [N], p1 [Pa], p2 [Pa]) (the pressures only where the model has
    them).  Friction is not included (see module notes).

    Attributes
    ----------
    model : str
        Registry name.
    params : DeviceParams
        Parameters.
    x0 : ndarray
        Operating state [state units].
    u0 : ndarray
        Operating input (y0 [m], v0 [m/s], a0 [m/s^2]).
    A, B, C, D : ndarray
        Matrices, shapes (n, n), (n, 3), (n_out, n), (n_out, 3).
    state_names, output_names : tuple of str
        Signal names.
    xdot0 : ndarray
        rhs at the operating point (zero at an equilibrium).
    jacobian : str
        ``"analytic"`` (model.jacobian) or ``"central differences"``.
    """

    model: str
    params: DeviceParams
    x0: np.ndarray
    u0: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    output_names: tuple[str, ...]
    xdot0: np.ndarray
    jacobian: str

    def __post_init__(self) -> None:
        for name in ("x0", "u0", "A", "B", "C", "D", "xdot0"):
            getattr(self, name).setflags(write=False)

    @property
    def n_states(self) -> int:
        """Number of states."""
        return self.A.shape[0]

    @property
    def system(self) -> control.StateSpace:
        """The three-input StateSpace (inputs :data:`INPUT_NAMES`, outputs, states named)."""
        return control.ss(self.A, self.B, self.C, self.D, inputs=list(INPUT_NAMES),
                          outputs=list(self.output_names), states=list(self.state_names),
                          name=f"{self.model}_lin")

    @property
    def is_proper_in_stroke(self) -> bool:
        """True if the stroke-to-output map is proper (no direct rate/acceleration feed)."""
        return bool(np.all(self.D[:, 1:] == 0.0) and np.all(self.B[:, 2] == 0.0))

    def frequency_response(self, frequencies_hz, output: str = "force") -> np.ndarray:
        """Complex stroke-to-``output`` response at ``frequencies_hz`` [Hz].

        K(i w) = C (i w I - A)^-1 (b_y + i w b_v - w^2 b_a) + d_y + i w d_v - w^2 d_a,
        solved directly (no transfer-function coefficients, so no loss of
        accuracy from the invariant modes of the full model).

        Returns
        -------
        ndarray of complex
            [N/m] for the force, [Pa/m] for a pressure.
        """
        if output not in self.output_names:
            raise ParameterError(
                f"unknown output {output!r}; valid: {', '.join(self.output_names)}")
        k = self.output_names.index(output)
        f = np.atleast_1d(np.asarray(frequencies_hz, float))
        out = np.empty(f.size, complex)
        n = self.n_states
        for i, fi in enumerate(f):
            s = 2j * math.pi * fi
            bu = self.B[:, 0] + s * self.B[:, 1] + s * s * self.B[:, 2]
            du = self.D[k, 0] + s * self.D[k, 1] + s * s * self.D[k, 2]
            if n:
                x = np.linalg.solve(s * np.eye(n) - self.A, bu)
                out[i] = self.C[k] @ x + du
            else:
                out[i] = du
        return out

    @renamed(amplitude_m="amplitude", frequency_hz="frequency")
    def state_phasor(self, frequency: float, amplitude: float) -> np.ndarray:
        """Complex state amplitudes X under y = Y sin(w t) (sine convention).

        The linear periodic state is x(t) = x0 + Im(X e^{i w t}); x(0) = x0 +
        Im X.  Used to warm-start nonlinear steady states.
        """
        s = 2j * math.pi * frequency
        bu = self.B[:, 0] + s * self.B[:, 1] + s * s * self.B[:, 2]
        return np.linalg.solve(s * np.eye(self.n_states) - self.A, bu) * amplitude

    def stroke_system(self) -> control.StateSpace:
        """Proper StateSpace from ``'stroke'`` [m] to the outputs, by z = x - b_v y.

        States are named ``NAME*`` (z = x - b_v y, in the units of x).

        Raises
        ------
        ParameterError
            For the algebraic models with a rate or acceleration feed-through
            (dashpot, dashpot_inerter, inerter): improper, use
            :meth:`transfer_function` or :attr:`system`.
        """
        if not self.is_proper_in_stroke:
            raise ParameterError(
                f"model {self.model!r}: stroke-to-force map is improper (force depends directly "
                "on stroke rate or acceleration); use .transfer_function() or .system")
        bv = self.B[:, 1]
        b = (self.A @ bv + self.B[:, 0]).reshape(-1, 1)
        d = (self.C @ bv + self.D[:, 0]).reshape(-1, 1)
        return control.ss(self.A, b, self.C, d, inputs=["stroke"],
                          outputs=list(self.output_names),
                          states=[f"{n}*" for n in self.state_names],
                          name=f"{self.model}_stroke")

    def minimal(self, tol: float = 1e-9) -> control.StateSpace:
        """Controllable and observable part of :meth:`stroke_system` (force output).

        States are scaled by ``model.state_scales`` before rank decisions
        (SVD, relative tolerance ``tol``); the returned states are
        combinations of the scaled states, named ``xm[i]``.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> lin = linearize("full", preset("reference"))
        >>> lin.n_states, lin.minimal().nstates     # two invariant modes removed... and more
        (5, 2)
        """
        sys = self.stroke_system()
        k = self.output_names.index("force")
        n = self.n_states
        if n == 0:
            return control.ss(np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)),
                              sys.D[k:k + 1], inputs=["stroke"], outputs=["force"])
        T = np.diag(self._scales())
        Ti = np.diag(1.0 / np.diag(T))
        A = Ti @ sys.A @ T
        b = Ti @ sys.B
        c = sys.C[k:k + 1] @ T
        d = sys.D[k:k + 1]
        # controllable subspace
        Wc = np.hstack([np.linalg.matrix_power(A / self._rate(A), i) @ b for i in range(n)])
        U, sv, _ = np.linalg.svd(Wc)
        r = int(np.sum(sv > tol * sv[0])) if sv[0] > 0 else 0
        Uc = U[:, :r]
        A1, b1, c1 = Uc.T @ A @ Uc, Uc.T @ b, c @ Uc
        # observable part of it
        if r:
            Wo = np.vstack([c1 @ np.linalg.matrix_power(A1 / self._rate(A1), i)
                            for i in range(r)])
            _, so, Vt = np.linalg.svd(Wo)
            q = int(np.sum(so > tol * so[0])) if so[0] > 0 else 0
            Vo = Vt[:q].T
            A1, b1, c1 = Vo.T @ A1 @ Vo, Vo.T @ b1, c1 @ Vo
        return control.ss(A1, b1, c1, d, inputs=["stroke"], outputs=["force"],
                          states=[f"xm[{i}]" for i in range(A1.shape[0])],
                          name=f"{self.model}_min")

    def transfer_function(self, tol: float = 1e-9) -> control.TransferFunction:
        """Stroke-to-force :class:`control.TransferFunction` (minimal order).

        Proper models through :meth:`minimal`; the algebraic models give
        their polynomial d_y + d_v s + d_a s^2 (improper where d_v, d_a != 0).
        """
        k = self.output_names.index("force")
        if not self.is_proper_in_stroke:
            if self.n_states:
                raise ParameterError(f"model {self.model!r}: improper with states; "
                                     "not supported")
            d = self.D[k]
            return _tf([d[2], d[1], d[0]], [1.0], self.model)
        m = self.minimal(tol)
        if m.nstates == 0:
            return _tf([float(m.D[0, 0])], [1.0], self.model)
        g = control.ss2tf(m)
        num = np.trim_zeros(np.asarray(g.num[0][0], float), "f")
        den = np.asarray(g.den[0][0], float)
        num = np.where(np.abs(num) < 1e-12 * np.max(np.abs(num)), 0.0, num)
        return _tf(num / den[0], den / den[0], self.model)

    def _scales(self) -> np.ndarray:
        sc = np.asarray(get_model(self.model).state_scales(self.params), float)
        return np.where(sc > 0, sc, 1.0)

    @staticmethod
    def _rate(A) -> float:
        return max(float(np.max(np.abs(A))), 1e-300)


def linearize(model: str | DeviceModel, params: DeviceParams, x0=None, u0=None
              ) -> Linearization:
    """Linearize ``model`` about (x0, u0), default rest at p0 with zero stroke.

    d rhs/dx from ``model.jacobian`` (analytic, or the compiled central
    differences of a composition with kinematic or fluid effects); d rhs/du,
    C and D by central differences with steps eps^(1/3) times the state
    scales and one Richardson step (which cancels the O(h) error at the kink
    of the quadratic loss at zero flow) over u = (y, v, a) and x (the models
    are affine in v and a).  The parameter set's friction is not linearized
    (module notes); an add-on effect without a small-signal model at rest
    (Coulomb friction, freeplay) raises ParameterError naming it.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model.
    params : DeviceParams
        Device.
    x0 : array, optional
        Operating state (default ``model.initial_state(params, y0)``).
    u0 : array of 3, optional
        Operating input (y0 [m], v0 [m/s], a0 [m/s^2]) (default zeros).

    Returns
    -------
    Linearization

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> lin = linearize("inertial_2state", preset("reference"))
    >>> lin.system.input_labels, lin.system.output_labels
    (['stroke', 'stroke_rate', 'stroke_acceleration'], ['force'])
    >>> lin.jacobian
    'analytic'
    """
    m = get_model(model)
    p = _check_params(params)
    m.check_params(p)
    for e in m.effects:  # each effect says whether the equations at rest hold it
        e.check_small_signal(p)
    u0 = np.zeros(3) if u0 is None else np.asarray(u0, float).reshape(-1)
    if u0.size != 3 or not np.all(np.isfinite(u0)):
        raise ParameterError(f"u0 must be 3 finite numbers (y [m], v [m/s], a [m/s^2]), got {u0}")
    if abs(u0[0]) >= p.stroke_limit:
        raise ParameterError(f"operating stroke |y0| = {abs(u0[0]):g} m must be < "
                             f"{p.stroke_limit:g} m (V0/A_p)")
    x0 = m.initial_state(p, float(u0[0])) if x0 is None else np.asarray(x0, float).reshape(-1)
    n = m.n_states
    if x0.size != n or not np.all(np.isfinite(x0)):
        raise ParameterError(f"x0 must have {n} finite entries ({', '.join(m.state_names)})")
    u0t = tuple(u0)
    f0 = np.asarray(m.rhs(0.0, x0, u0t, p), float)
    A = np.zeros((n, n))
    kind = "analytic" if m.analytic_jacobian else "central differences (compiled)"
    hx = _rel_steps(np.asarray(m.state_scales(p), float)) if n else np.zeros(0)
    names = _output_names(m)
    C = np.zeros((len(names), n))
    for j in range(n):
        C[:, j] = _central(lambda x: _outputs(m, p, x, u0t), x0, j, hx[j])
    if n:
        A = np.asarray(m.jacobian(0.0, x0, u0t, p), float)
    B = np.zeros((n, 3))
    D = np.zeros((len(names), 3))
    hu = _u_steps(p)
    for j in range(3):
        if n:
            B[:, j] = _central(lambda u: m.rhs(0.0, x0, tuple(u), p), u0, j, hu[j])
        D[:, j] = _central(lambda u: _outputs(m, p, x0, tuple(u)), u0, j, hu[j])
    return Linearization(model=m.name, params=p, x0=x0.copy(), u0=u0.copy(), A=A, B=B, C=C, D=D,
                         state_names=m.state_names, output_names=names, xdot0=f0, jacobian=kind)
