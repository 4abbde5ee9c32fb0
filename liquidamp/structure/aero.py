"""Thin-airfoil aerodynamics of the typical section (Theodorsen and its reductions).

Nondimensional form used throughout (Hodges & Pierce 2011, Ch. 5): time
``tau = omega_theta t``, plunge ``h/b`` (positive *down*), pitch ``theta``
(positive nose up), speed ``V = U/(b omega_theta)``, Laplace variable
``p`` (in units of ``omega_theta``), reduced frequency ``k = omega b/U``.
The generalized aerodynamic forces on ``q = [h/b, theta]`` (the lift ``-L``
on the plunge equation divided by ``m b omega_theta^2``, the moment about
the reference point divided by ``m b^2 omega_theta^2``) are

.. math::

   Q(p) = p^2 M_{nc} + p V D_{nc} + \\frac{2V}{\\mu} C\\, l\\,(p\\, w_1 + V w_0)

with the apparent-mass matrices

.. math::

   M_{nc} = \\frac{1}{\\mu}\\begin{bmatrix}-1 & a\\\\ a & -(1/8 + a^2)\\end{bmatrix},\\qquad
   D_{nc} = \\frac{1}{\\mu}\\begin{bmatrix}0 & -1\\\\ 0 & -(1/2 - a)\\end{bmatrix},

``l = [-1, 1/2 + a]^T`` (lift acting at the quarter chord),
``w1 = [1, 1/2 - a]`` and ``w0 = [0, 1]`` (the three-quarter-chord
downwash ``w = p h/b + V theta + (1/2 - a) p theta``), and ``C`` the lift
deficiency function.  The models:

``steady``
    ``Q = (2 V^2/mu) l w0`` only (lift slope 2 pi at the current angle).
``quasi-steady``
    Theodorsen's loads with ``C = 1`` (apparent mass kept).
``theodorsen``
    ``C(k) = H1(k) / (H1(k) + i H0(k))`` with Hankel functions of the second
    kind (frequency domain only).
``jones``
    R. T. Jones' two-lag approximation
    ``C(s) = 1 - 0.165 s/(s + 0.0455) - 0.335 s/(s + 0.3)`` with
    ``s = p/V`` (reduced Laplace variable ``s b/U``); exact rational, so it
    has a state-space (time-domain) realization with two lag states.

References
----------
.. [1] T. Theodorsen, "General theory of aerodynamic instability and the
   mechanism of flutter", NACA Report 496, 1935.
.. [2] R. T. Jones, "The unsteady lift of a wing of finite aspect ratio",
   NACA Report 681, 1940.
.. [3] R. L. Bisplinghoff, H. Ashley, R. L. Halfman, *Aeroelasticity*,
   Addison-Wesley, 1955, Sec. 5-6 (eqs. 5-310, 5-311; Table 5-1 of C(k)).
.. [4] D. H. Hodges, G. A. Pierce, *Introduction to Structural Dynamics and
   Aeroelasticity*, 2nd ed., Cambridge University Press, 2011, Ch. 5.
"""

from __future__ import annotations

import numpy as np
from scipy.special import hankel2

from liquidamp.errors import ParameterError, check_choice

__all__ = [
    "AERO_MODELS",
    "STATE_SPACE_MODELS",
    "JONES_COEFFICIENTS",
    "theodorsen",
    "jones",
    "lift_deficiency",
    "aero_matrices",
]

AERO_MODELS = ("steady", "quasi-steady", "theodorsen", "jones")
"""Names of the aerodynamic models."""

STATE_SPACE_MODELS = ("steady", "quasi-steady", "jones")
"""Models with a finite state-space (time-domain) realization."""

JONES_COEFFICIENTS = ((0.165, 0.0455), (0.335, 0.3))
"""R. T. Jones' ``(A_j, b_j)``: ``C(s) = 1 - sum A_j s/(s + b_j)`` [-]."""


def theodorsen(k):
    """Theodorsen's lift deficiency function C(k) = F + iG (exact).

    Parameters
    ----------
    k : float or array
        Reduced frequency k = omega b/U >= 0 [-]; ``C(0) = 1``.

    Returns
    -------
    complex or ndarray of complex

    Examples
    --------
    >>> c = theodorsen(0.5)
    >>> round(c.real, 4), round(c.imag, 4)   # tabulated: F = 0.5979, G = -0.1507
    (0.5979, -0.1507)
    >>> theodorsen(0.0)
    (1+0j)
    """
    k_arr = np.asarray(k, dtype=float)
    if np.any(~np.isfinite(k_arr)) or np.any(k_arr < 0.0):
        raise ParameterError(f"reduced frequency k must be finite and >= 0 [-], got {k!r}")
    safe = np.where(k_arr > 0.0, k_arr, 1.0)
    h1, h0 = hankel2(1, safe), hankel2(0, safe)
    c = np.where(k_arr > 0.0, h1 / (h1 + 1j * h0), 1.0 + 0.0j)
    return complex(c) if c.ndim == 0 else c


def jones(s):
    """R. T. Jones' approximation C(s) = 1 - 0.165 s/(s+0.0455) - 0.335 s/(s+0.3).

    Parameters
    ----------
    s : complex or array
        Reduced Laplace variable ``s b/U`` [-]; ``s = i k`` for harmonic motion.

    Examples
    --------
    >>> c = jones(0.5j)
    >>> round(c.real, 3), round(c.imag, 3)   # exact C(0.5) = 0.598 - 0.151i
    (0.59, -0.163)
    """
    s = np.asarray(s, dtype=complex)
    c = np.ones_like(s)
    for A, b in JONES_COEFFICIENTS:
        c = c - A * s / (s + b)
    return complex(c) if c.ndim == 0 else c


def lift_deficiency(model: str, k):
    """C at reduced frequency ``k`` [-] for a frequency-domain use of ``model``.

    ``steady`` and ``quasi-steady`` give 1; ``theodorsen`` the exact
    function; ``jones`` the approximation at ``s = i k``.

    Examples
    --------
    >>> lift_deficiency("quasi-steady", 0.3)
    (1+0j)
    """
    check_choice("aerodynamic model", model, AERO_MODELS)
    if model == "theodorsen":
        return theodorsen(k)
    if model == "jones":
        return jones(1j * np.asarray(k, dtype=float))
    return 1.0 + 0.0j


def aero_matrices(a: float, mu: float):
    """Nondimensional building blocks ``Mnc, Dnc, l, w1, w0`` of the loads (module notes).

    Parameters
    ----------
    a : float
        Reference-point (elastic axis) position aft of mid-chord [semichords].
    mu : float
        Mass ratio m/(pi rho b^2) [-].

    Examples
    --------
    >>> Mnc, Dnc, l, w1, w0 = aero_matrices(-0.2, 20.0)
    >>> l.tolist(), w1.tolist()
    ([[-1.0], [0.3]], [[1.0, 0.7]])
    """
    Mnc = np.array([[-1.0, a], [a, -(0.125 + a * a)]]) / mu
    Dnc = np.array([[0.0, -1.0], [0.0, -(0.5 - a)]]) / mu
    l = np.array([[-1.0], [0.5 + a]])
    w1 = np.array([[1.0, 0.5 - a]])
    w0 = np.array([[0.0, 1.0]])
    return Mnc, Dnc, l, w1, w0
