"""Device parameters (Table 1-2 of Titurus 2018) and derived quantities.

:class:`DeviceParams` is a frozen, validated dataclass in SI.  Change it with
:func:`dataclasses.replace`; every replacement is validated again.  The loss
coefficients ``c1``, ``c2`` and the inertance factor ``S_t`` default to the
paper's geometric estimates (``c1 = 8 pi mu l_t / A_t^2``,
``c2 = rho_l / (2 C_De^2 A_t^2)``, ``S_t = l_t / A_t``) when they are not
given; the estimates are filled in at construction, so after changing the
channel geometry with ``replace`` pass ``c1=None`` (etc.) to re-derive them.

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, Tables 1-3, eqs. (2), (5), (6), (16), (19).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from liquidamp.device.fluid import air_fraction, bulk_modulus_gholizadeh
from liquidamp.errors import (
    ParameterError,
    check_choice,
    check_in_range,
    check_nonnegative,
    check_positive,
)

__all__ = ["DeviceParams", "C_DE", "BULK_LAWS", "initial_c1", "initial_c2"]

#: Combined entry/exit discharge coefficient used for the initial c2 (paper, Sec. IV.C).
C_DE = 0.48
#: Bulk-modulus laws a parameter set may select.
BULK_LAWS = ("gholizadeh", "constant")


def initial_c1(mu: float, l_t: float, A_t: float) -> float:
    """Hagen-Poiseuille estimate c1 = 8 pi mu l_t / A_t^2 [kg m^-4 s^-1].

    Examples
    --------
    >>> f"{initial_c1(8.9e-4, 0.75, 4.0e-6):.4e}"
    '1.0485e+09'
    """
    return 8.0 * math.pi * mu * l_t / A_t**2


def initial_c2(rho_l: float, A_t: float, C_De: float = C_DE) -> float:
    """Entry/exit loss estimate c2 = rho_l / (2 C_De^2 A_t^2) [kg m^-7].

    Examples
    --------
    >>> f"{initial_c2(998.2, 4.0e-6):.4e}"
    '1.3539e+14'
    """
    return rho_l / (2.0 * C_De**2 * A_t**2)


@dataclass(frozen=True)
class DeviceParams:
    """Parameters of the two-chamber liquid device, SI units.

    Parameters
    ----------
    mu : float
        Dynamic viscosity of the liquid [Pa s].
    rho_l : float
        Liquid density; also the reference density rho0 of both chambers at
        ``p0`` and the density of the channel flow (paper: rho_12 = rho_l) [kg/m^3].
    B_l : float
        Bulk modulus of the pure liquid [Pa].
    V01, V02 : float
        Working volumes of chambers 1 and 2 at zero stroke [m^3].
    A_p : float
        Wetted piston area [m^2].
    A_t : float
        Channel cross-section [m^2].
    l_t : float
        Channel length [m].
    p0 : float
        Filling (reference) pressure [Pa].
    n : float
        Polytropic coefficient of the air, in [1, 1.67] [-].
    inv_gamma1, inv_gamma2 : float
        Gas-to-liquid volume ratio 1/gamma of each chamber at ``p0``
        (Table 2 lists this; eq. 2 uses X0 = 1/(1 + gamma)) [-].
    c1 : float, optional
        Linear loss coefficient of eq. (5) in volumetric form,
        dp = c1 q + c2 q|q| [kg m^-4 s^-1].  Default ``8 pi mu l_t / A_t^2``.
    c2 : float, optional
        Quadratic loss coefficient [kg m^-7].  Default ``rho_l/(2 C_De^2 A_t^2)``.
    S_t : float, optional
        Channel inertance factor l_te/A_te [1/m].  Default ``l_t / A_t``.
    friction_N : float
        Coulomb friction |F_f| added to the load-cell force as
        |F_f| sign(dy/dt) [N].  0 for none.
    bulk_law : {"gholizadeh", "constant"}
        Bulk-modulus law of the chambers: eq. (2), or constant at its value
        at ``p0`` (the assumption of eqs. 12-18).
    name : str
        Label used in reports (does not change any answer).

    Notes
    -----
    Validity: the stroke must keep both chambers open, |y| < V0i / A_p
    (checked by the simulation before it starts); pressures must stay > 0.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("paper_initial")
    >>> round(p.b_L, 1)
    89.4
    >>> round(p.A_p * 1e6, 2)
    691.15
    """

    mu: float
    rho_l: float
    B_l: float
    V01: float
    V02: float
    A_p: float
    A_t: float
    l_t: float
    p0: float
    n: float
    inv_gamma1: float
    inv_gamma2: float
    c1: float | None = None
    c2: float | None = None
    S_t: float | None = None
    friction_N: float = 0.0
    bulk_law: str = "gholizadeh"
    name: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        for fname, unit in (
            ("mu", "Pa s"),
            ("rho_l", "kg/m^3"),
            ("B_l", "Pa"),
            ("V01", "m^3"),
            ("V02", "m^3"),
            ("A_p", "m^2"),
            ("A_t", "m^2"),
            ("l_t", "m"),
            ("p0", "Pa"),
        ):
            object.__setattr__(self, fname, check_positive(fname, getattr(self, fname), unit))
        object.__setattr__(self, "n", check_in_range("n", self.n, 1.0, 1.67, "-"))
        for fname in ("inv_gamma1", "inv_gamma2"):
            object.__setattr__(self, fname, check_nonnegative(fname, getattr(self, fname), "-"))
        if self.c1 is None:
            object.__setattr__(self, "c1", initial_c1(self.mu, self.l_t, self.A_t))
        if self.c2 is None:
            object.__setattr__(self, "c2", initial_c2(self.rho_l, self.A_t))
        if self.S_t is None:
            object.__setattr__(self, "S_t", self.l_t / self.A_t)
        object.__setattr__(self, "c1", check_nonnegative("c1", self.c1, "kg m^-4 s^-1"))
        object.__setattr__(self, "c2", check_nonnegative("c2", self.c2, "kg m^-7"))
        object.__setattr__(self, "S_t", check_nonnegative("S_t", self.S_t, "1/m"))
        if self.c1 == 0.0 and self.c2 == 0.0:
            raise ParameterError(
                "c1 and c2 are both 0: the channel has no resistance; "
                "at least one must be > 0 [kg m^-4 s^-1], [kg m^-7]"
            )
        object.__setattr__(
            self, "friction_N", check_nonnegative("friction_N", self.friction_N, "N")
        )
        check_choice("bulk_law", self.bulk_law, BULK_LAWS)

    # ----- convenience -------------------------------------------------
    def replace(self, **changes) -> DeviceParams:
        """Return a validated copy with ``changes`` applied (see dataclasses.replace).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> preset("reference").replace(friction_N=30.0).friction_N
        30.0
        """
        return dataclasses.replace(self, **changes)

    def scaled(self, **multipliers: float) -> DeviceParams:
        """Return a copy with named fields multiplied, e.g. ``scaled(c1=3.56)``.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> p = preset("paper_initial")
        >>> p.scaled(c1=2.0).c1 / p.c1
        2.0
        """
        changes = {}
        for key, factor in multipliers.items():
            if key not in SCALABLE:
                raise ParameterError(
                    f"cannot scale {key!r}; scalable parameters: {', '.join(SCALABLE)}"
                )
            changes[key] = getattr(self, key) * check_nonnegative(f"multiplier of {key}", factor)
        return dataclasses.replace(self, **changes)

    # ----- derived quantities -----------------------------------------
    @property
    def X01(self) -> float:
        """Air volume fraction of chamber 1, X0 = 1/(1 + gamma1) [-]."""
        return air_fraction(self.inv_gamma1)

    @property
    def X02(self) -> float:
        """Air volume fraction of chamber 2, X0 = 1/(1 + gamma2) [-]."""
        return air_fraction(self.inv_gamma2)

    @property
    def rho0(self) -> float:
        """Density of both chambers at ``p0`` (taken as rho_l, see class notes) [kg/m^3]."""
        return self.rho_l

    @property
    def g1(self) -> float:
        """Mass-flow linear loss coefficient g1 = c1 / rho_l [1/(m s)]."""
        return self.c1 / self.rho_l

    @property
    def g2(self) -> float:
        """Mass-flow quadratic loss coefficient g2 = c2 / rho_l^2 [1/(kg m)]."""
        return self.c2 / self.rho_l**2

    @property
    def L_t(self) -> float:
        """Fluid inertance of the channel L = rho_l S_t [kg/m^4]."""
        return self.rho_l * self.S_t

    @property
    def b_L(self) -> float:
        """Fluid-induced mechanical inertance b_L = rho_l S_t A_p^2, eq. (19) [kg]."""
        return self.rho_l * self.S_t * self.A_p**2

    @property
    def c_L(self) -> float:
        """Laminar (viscous) damping coefficient c_L = c1 A_p^2, eq. (19) [N s/m]."""
        return self.c1 * self.A_p**2

    def bulk_modulus_at(self, p: float, chamber: int) -> float:
        """Bulk modulus of chamber 1 or 2 at pressure ``p`` under ``bulk_law`` [Pa]."""
        X0 = self.X01 if chamber == 1 else self.X02
        if self.bulk_law == "constant":
            p = self.p0
        return bulk_modulus_gholizadeh(p, self.B_l, X0, self.p0, self.n)

    @property
    def B01(self) -> float:
        """Bulk modulus of chamber 1 at ``p0`` (eq. 2) [Pa]."""
        return bulk_modulus_gholizadeh(self.p0, self.B_l, self.X01, self.p0, self.n)

    @property
    def B02(self) -> float:
        """Bulk modulus of chamber 2 at ``p0`` (eq. 2) [Pa]."""
        return bulk_modulus_gholizadeh(self.p0, self.B_l, self.X02, self.p0, self.n)

    @property
    def B_eff(self) -> float:
        """Effective damper stiffness factor B = B1/V01 + B2/V02 of eq. (18) at rest [Pa/m^3]."""
        return self.B01 / self.V01 + self.B02 / self.V02

    @property
    def k_D(self) -> float:
        """Equivalent stiffness of the Maxwell unit k_D = A_p^2 (B1/V01 + B2/V02) [N/m].

        Equals the paper's 2 B0 A_p^2 / V0 for a symmetric device (eq. 16).
        """
        return self.A_p**2 * self.B_eff

    @property
    def T_D(self) -> float:
        """Relaxation time of the Maxwell unit T_D = c1 / (B1/V01 + B2/V02) [s].

        With c1 a resistance (dp = c1 q) this is c1 V0 / (2 B0) for a symmetric
        device; the paper's V0/(2 B0 c1) writes c1 as a conductance.  Note
        c_L = k_D T_D.
        """
        return self.c1 / self.B_eff

    @property
    def stroke_limit(self) -> float:
        """Largest admissible stroke magnitude min(V01, V02) / A_p [m]."""
        return min(self.V01, self.V02) / self.A_p

    def derived(self) -> dict[str, float]:
        """All parameters and derived quantities as ``{"name [unit]": value}``.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> d = preset("paper_initial").derived()
        >>> f"{d['c1 [kg m^-4 s^-1]']:.4e}", round(d["b_L [kg]"], 1)
        ('1.0485e+09', 89.4)
        """
        return {
            "mu [Pa s]": self.mu,
            "rho_l [kg/m^3]": self.rho_l,
            "B_l [Pa]": self.B_l,
            "V01 [m^3]": self.V01,
            "V02 [m^3]": self.V02,
            "A_p [m^2]": self.A_p,
            "A_t [m^2]": self.A_t,
            "l_t [m]": self.l_t,
            "p0 [Pa]": self.p0,
            "n [-]": self.n,
            "inv_gamma1 [-]": self.inv_gamma1,
            "inv_gamma2 [-]": self.inv_gamma2,
            "X01 [-]": self.X01,
            "X02 [-]": self.X02,
            "c1 [kg m^-4 s^-1]": self.c1,
            "c2 [kg m^-7]": self.c2,
            "S_t [1/m]": self.S_t,
            "g1 [1/(m s)]": self.g1,
            "g2 [1/(kg m)]": self.g2,
            "L_t [kg/m^4]": self.L_t,
            "b_L [kg]": self.b_L,
            "c_L [N s/m]": self.c_L,
            "B01 [Pa]": self.B01,
            "B02 [Pa]": self.B02,
            "k_D [N/m]": self.k_D,
            "T_D [s]": self.T_D,
            "friction_N [N]": self.friction_N,
            "stroke_limit [m]": self.stroke_limit,
        }


#: Fields that :meth:`DeviceParams.scaled` may multiply.
SCALABLE = ("mu", "rho_l", "B_l", "V01", "V02", "A_p", "A_t", "l_t", "inv_gamma1", "inv_gamma2",
            "c1", "c2", "S_t", "friction_N")
