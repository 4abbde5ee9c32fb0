"""The conserved quantities of a device model on a torus (the two-frequency problem).

A sealed device keeps its liquid mass (and, per chamber, the relation of
density to pressure along its rest-state curve); the harmonic balance of
:func:`~liquidamp.analysis.response.dual_frequency.dual_frequency_stiffness`
(which re-exports :class:`TorusInvariants` and :func:`torus_invariants`)
holds them at their rest values, as the time-domain run from rest does.
Equations and references in :class:`TorusInvariants`.
"""

from __future__ import annotations

import math

import numpy as np

from liquidamp.device import kernels as K
from liquidamp.device.fluid import bulk_modulus_gholizadeh
from liquidamp.device.models import DeviceModel
from liquidamp.errors import (
    ParameterError,
)

__all__ = ["TorusInvariants", "torus_invariants"]


class TorusInvariants:
    """The conserved quantities of a device model, evaluated on many states at once.

    Chamber models (eqs. 10, 11): in each chamber ln rho_i - ln r_i(p_i),
    r_i the density on the rest-state pressure curve (0 from rest), and the
    total mass rho1 V1 + rho2 V2 [kg]; constant-bulk models with chamber
    pressures (eqs. 13, 17): the total mass r1(p1) V1 + r2(p2) V2.  The
    chamber volumes follow the piston stroke: the ``y_piston`` (series
    compliance) or ``y_fp`` (freeplay) state where present, else the rod
    stroke.  With series compliance also the balance of the massless piston,
    k (y - y_piston) - F_fluid [N] (0 from rest; the effect holds it through
    its rate, so its constant is an invariant too), or y - y_piston [m] for
    a rigid link.

    The rest-state curve of eq. (2) integrates in closed form but for a
    term of order (p - p0) / B_l: with r = (p0 / p)^(1/n),
    ln(r_i / rho0) = -ln(1 - X0 + X0 r) + (1 - X0) / B_l
    integral_{p0}^{p} dp' / (1 - X0 + X0 r(p')), the last integral by
    8-point Gauss-Legendre quadrature (it is smooth and its whole share is
    below 1e-4 of the first term at these pressures).

    Parameters
    ----------
    model : DeviceModel
        The model (any effects but cavitation).
    params : DeviceParams
        Its parameters.
    kind : {"chamber", "pressure", None}
        The base family's conserved quantities (None: none).

    Attributes
    ----------
    target : ndarray
        The values at rest (what the time-domain run from rest keeps).
    names : tuple of str
        What each value is.
    """

    def __init__(self, model: DeviceModel, params, kind: str | None):
        self.model, self.params, self.kind = model, params, kind
        names = model.state_names
        nb = model.n_base_states
        self.ip = None
        fp = model.effect("freeplay")
        for state in ("y_piston", "y_fp"):  # innermost kinematic effect first
            if state == "y_fp" and fp is not None and not fp.fluid_behind:
                continue  # a dead band that drives only friction: the fluid is on the rod
            if state in names[nb:]:
                self.ip = names.index(state)
                break
        out = []
        if kind is not None:
            self.i1, self.i2 = names.index("p1"), names.index("p2")
        if kind == "chamber":
            self.r1, self.r2 = names.index("rho1"), names.index("rho2")
            out += ["ln(rho1/r1(p1))", "ln(rho2/r2(p2))", "mass [kg]"]
        elif kind == "pressure":
            out += ["mass [kg]"]
        comp = model.effect("series_compliance")
        self.k = None
        if comp is not None:
            spec, prm, _ = model.packed(params)
            self.k = comp.stiffness_N_per_m
            self.ic = names.index("y_piston")
            # the fluid force is linear in the base states: its gradient, from the kernels
            self.cF = np.array([K.state_force(spec[K.S_MID], e, prm) for e in np.eye(nb)])
            out += ["piston balance [N]" if math.isfinite(self.k) else "y - y_piston [m]"]
        self.names = tuple(out)
        self._gl = np.polynomial.legendre.leggauss(8)
        x0 = model.initial_state(params, 0.0)
        vals, _ = self.evaluate(x0[:, None], np.zeros(1))
        self.target = vals[:, 0]

    def _log_curve(self, p, chamber: int):
        """ln(r(p) / rho0) on the rest-state curve [-] and its slope 1 / B(p) [1/Pa]."""
        q = self.params
        X0 = q.X01 if chamber == 1 else q.X02
        p = np.maximum(p, 1.0)  # the kernels' floor of the bulk law
        if self.kind == "pressure" or q.bulk_law == "constant":
            B0 = q.B01 if chamber == 1 else q.B02
            return (p - q.p0) / B0, np.full_like(p, 1.0 / B0)
        n, Bl, p0 = q.n, q.B_l, q.p0
        lr = -np.log1p(X0 * ((p0 / p) ** (1.0 / n) - 1.0))
        x, w = self._gl
        pp = 0.5 * (p - p0)[:, None] * x[None, :] + 0.5 * (p + p0)[:, None]
        integrand = 1.0 / (1.0 - X0 + X0 * (p0 / pp) ** (1.0 / n))
        lr = lr + (1.0 - X0) / Bl * 0.5 * (p - p0) * (integrand @ w)
        return lr, 1.0 / bulk_modulus_gholizadeh(p, Bl, X0, p0, n)

    def evaluate(self, X, Y):
        """Values (m, N) and gradients (m, n, N) at states X (n, N), rod strokes Y (N,)."""
        q = self.params
        n, N = X.shape
        vals = np.empty((len(self.names), N))
        G = np.zeros((len(self.names), n, N))
        c = 0
        if self.kind is not None:
            yp = X[self.ip] if self.ip is not None else Y
            V1, V2 = q.V01 - q.A_p * yp, q.V02 + q.A_p * yp
        if self.kind == "chamber":
            for c, (ip, ir) in enumerate(((self.i1, self.r1), (self.i2, self.r2))):
                lr, dlr = self._log_curve(X[ip], c + 1)
                vals[c] = np.log(np.maximum(X[ir], 1e-300) / q.rho0) - lr
                G[c, ir] = 1.0 / X[ir]
                G[c, ip] = -dlr
            rho1, rho2 = X[self.r1], X[self.r2]
            vals[2] = rho1 * V1 + rho2 * V2
            G[2, self.r1], G[2, self.r2] = V1, V2
            if self.ip is not None:
                G[2, self.ip] = q.A_p * (rho2 - rho1)
            c = 3
        elif self.kind == "pressure":
            l1, d1 = self._log_curve(X[self.i1], 1)
            l2, d2 = self._log_curve(X[self.i2], 2)
            r1, r2 = q.rho0 * np.exp(l1), q.rho0 * np.exp(l2)
            vals[0] = r1 * V1 + r2 * V2
            G[0, self.i1], G[0, self.i2] = r1 * d1 * V1, r2 * d2 * V2
            if self.ip is not None:
                G[0, self.ip] = q.A_p * (r2 - r1)
            c = 1
        if self.k is not None:
            nb = self.cF.size
            if math.isfinite(self.k):
                vals[c] = self.k * (Y - X[self.ic]) - self.cF @ X[:nb]
                G[c, :nb] = -self.cF[:, None]
                G[c, self.ic] = -self.k
            else:
                vals[c] = Y - X[self.ic]
                G[c, self.ic] = -1.0
        return vals, G


def torus_invariants(model: DeviceModel, params) -> TorusInvariants | None:
    """The invariants the harmonic balance must hold for ``model``, or None.

    Raises
    ------
    ParameterError
        For ``volumetric`` (eq. 14), which does not conserve mass and has no
        periodic state (its mean pressures drift), and for a model with the
        ``cavitation`` effect (cavity volumes are neutral states while the
        cavities are closed; the time route takes it).

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> from liquidamp.device.models import get_model
    >>> inv = torus_invariants(get_model("full"), preset("reference"))
    >>> inv.names, [round(float(v), 12) for v in inv.target[:2]]
    (('ln(rho1/r1(p1))', 'ln(rho2/r2(p2))', 'mass [kg]'), [0.0, 0.0])
    >>> from liquidamp.device.fluid import density_gholizadeh    # the closed form holds
    >>> p = preset("reference")
    >>> lr, _ = inv._log_curve(np.array([2e4, 3e5]), 1)
    >>> r = density_gholizadeh(np.array([2e4, 3e5]), p.rho0, p.B_l, p.X01, p.p0, p.n)
    >>> bool(np.allclose(lr, np.log(r / p.rho0), rtol=0.0, atol=1e-12))
    True
    >>> torus_invariants(get_model("maxwell"), preset("reference")) is None
    True
    >>> from liquidamp.device.effects import SeriesCompliance, with_effects
    >>> torus_invariants(with_effects(get_model("full"), SeriesCompliance(5e5)), p).names[3:]
    ('piston balance [N]',)
    """
    if model.effect("cavitation") is not None:
        raise ParameterError(
            f"model {model.name!r}: the harmonic balance does not take the 'cavitation' "
            "effect: while the cavities are closed their volumes are neutral states (any "
            "constant solves the equations), and while they open the chambers' "
            "density-pressure invariants no longer hold; use method='time'")
    if model.base == "volumetric":
        raise ParameterError(
            "model 'volumetric' (eq. 14) does not conserve mass: its mean pressures drift "
            "every cycle, so it has no steady state; use 'constant_bulk' (eq. 13)")
    kind = {"full": "chamber", "no_inertia": "chamber", "constant_bulk": "pressure",
            "inertial": "pressure"}.get(model.base)
    if kind is None and model.effect("series_compliance") is None:
        return None
    return TorusInvariants(model, params, kind)
