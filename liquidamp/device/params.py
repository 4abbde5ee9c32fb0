"""Device parameters (Tables 1-3 of Titurus 2018) and derived quantities.

:class:`DeviceParams` is a frozen, validated dataclass in SI.  Change it with
:func:`dataclasses.replace` (or :meth:`DeviceParams.replace`); every
replacement is validated again.

Derived quantities are derived
------------------------------
The channel's loss coefficients and inertance factor are *not* stored beside
the geometry they come from.  They are computed on access from the channel
geometry, the viscosity and an explicit calibration factor (issue #11):

- ``c1 = c1_factor * 8 pi mu l_t / A_t^2``   (Hagen-Poiseuille, eq. 5) [kg m^-4 s^-1]
- ``c2 = c2_factor * rho_l / (2 C_De^2 A_t^2)``   (entry/exit loss) [kg m^-7]
- ``S_t = S_t_factor * l_t / A_t``   (inertance factor l_te/A_te) [1/m]

The factors default to 1 (the paper's initial, geometric estimates).  Why
factors rather than stored values: Table 3 defines every published design
as final = alpha2 * alpha1 * initial value, i.e. a correction *of the
geometric estimate* (the real channel has bends, fittings and entry/exit
losses the estimate does not see).  Keeping the correction as a factor makes
"change ``mu``, ``l_t`` or ``A_t`` and ``c1``, ``c2``, ``S_t`` follow" true
for every preset, while each preset's numbers are the same products as
before (the presets' c1 = 3.56 x ... become ``c1_factor = 3.56``).

A user who *knows* a coefficient (a measured channel resistance, a sizing
rule) gives it as an absolute value: ``DeviceParams(..., c1=...)``,
``p.replace(c1=...)`` or ``c1 = ...`` in a device file.  An explicit value
wins over the geometric estimate and its factor; the inputs it makes
irrelevant (``mu`` once c1 is explicit, ``l_t`` once c1 and S_t are,
``A_t`` once all three are, a factor other than 1 beside an explicit value)
are listed by :meth:`DeviceParams.unused` and in :meth:`DeviceParams.derived`,
never dropped silently.  ``p.replace(c1=None)`` returns to the derived value.

:meth:`DeviceParams.scaled` multiplies a derived coefficient's factor, or
an explicit coefficient's value, so ``scaled(c1=3.56)`` means the same in
both cases; scaling an unused input by anything but 1 raises.

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

__all__ = ["DeviceParams", "C_DE", "BULK_LAWS", "DERIVABLE", "INPUT_NAMES", "SCALABLE",
           "initial_c1", "initial_c2", "initial_S_t"]

#: Combined entry/exit discharge coefficient used for the initial c2 (paper, Sec. IV.C).
C_DE = 0.48
#: Bulk-modulus laws a parameter set may select.
BULK_LAWS = ("gholizadeh", "constant")
#: Channel quantities derived from the geometry unless given explicitly, with their units.
DERIVABLE = {"c1": "kg m^-4 s^-1", "c2": "kg m^-7", "S_t": "1/m"}
#: The geometry inputs each derivable quantity comes from (rho_l is used elsewhere too).
_SOURCES = {"c1": ("mu", "l_t", "A_t"), "c2": ("A_t",), "S_t": ("l_t", "A_t")}
_FORMULA = {
    "c1": "c1 = c1_factor 8 pi mu l_t / A_t^2",
    "c2": "c2 = c2_factor rho_l / (2 C_De^2 A_t^2)",
    "S_t": "S_t = S_t_factor l_t / A_t",
}
_UNSET = object()  # keyword not given (None means "derive")


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


def initial_S_t(l_t: float, A_t: float) -> float:
    """Inertance factor of a straight channel S_t = l_t / A_t [1/m].

    Examples
    --------
    >>> initial_S_t(0.75, 4.0e-6)
    187500.0
    """
    return l_t / A_t


@dataclass(frozen=True, init=False)
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
    c1 : float or None, optional
        Explicit linear loss coefficient of eq. (5) in volumetric form,
        dp = c1 q + c2 q|q| [kg m^-4 s^-1].  None (default): derived,
        ``c1_factor * 8 pi mu l_t / A_t^2``.
    c2 : float or None, optional
        Explicit quadratic loss coefficient [kg m^-7].  None (default):
        derived, ``c2_factor * rho_l / (2 C_De^2 A_t^2)``.
    S_t : float or None, optional
        Explicit channel inertance factor l_te/A_te [1/m].  None (default):
        derived, ``S_t_factor * l_t / A_t``.
    friction_N : float
        Coulomb friction |F_f| added to the load-cell force as
        |F_f| sign(dy/dt) [N].  0 for none.
    bulk_law : {"gholizadeh", "constant"}
        Bulk-modulus law of the chambers: eq. (2), or constant at its value
        at ``p0`` (the assumption of eqs. 12-18).
    name : str
        Label used in reports (does not change any answer).
    c1_factor, c2_factor, S_t_factor : float, keyword-only
        Calibration factors on the geometric estimates, >= 0 [-] (default 1;
        the paper's alpha2 * alpha1 of Tables 2-3).  Ignored, and reported by
        :meth:`unused` when not 1, while the quantity is given explicitly.
    c1_explicit, c2_explicit, S_t_explicit : float or None, keyword-only
        The stored form of an explicit ``c1``, ``c2``, ``S_t`` (what
        :func:`dataclasses.replace` passes on).  ``c1=`` etc. take precedence
        over them, so ``replace(c1=...)`` and ``replace(c1=None)`` work.

    Notes
    -----
    Read ``c1``, ``c2``, ``S_t`` (and ``g1``, ``g2``, ``L_t``, ``b_L``, ``c_L``,
    ``k_D``, ``T_D``) as attributes; they are floats computed from the
    stored inputs (module notes).  Validity: the stroke must keep both
    chambers open, |y| < V0i / A_p (checked by the simulation before it
    starts); pressures must stay > 0.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> p = preset("paper_initial")
    >>> round(p.b_L, 1)
    89.4
    >>> round(p.A_p * 1e6, 2)
    691.15
    >>> ref = preset("reference")              # c1 = 3.56 x the Poiseuille estimate
    >>> ref.c1_factor, round(ref.replace(mu=2 * ref.mu).c1 / ref.c1, 12)
    (3.56, 2.0)
    >>> q = ref.replace(c1=2.0e9)              # explicit: mu no longer enters
    >>> q.c1, sorted(q.unused())
    (2000000000.0, ['c1_factor', 'mu'])
    >>> q.replace(c1=None).c1 == ref.c1        # back to the derived value
    True
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
    c1_factor: float = 1.0
    c2_factor: float = 1.0
    S_t_factor: float = 1.0
    c1_explicit: float | None = None
    c2_explicit: float | None = None
    S_t_explicit: float | None = None
    friction_N: float = 0.0
    bulk_law: str = "gholizadeh"
    name: str = field(default="", compare=False)

    def __init__(self, mu: float, rho_l: float, B_l: float, V01: float, V02: float,
                 A_p: float, A_t: float, l_t: float, p0: float, n: float,
                 inv_gamma1: float, inv_gamma2: float, c1=_UNSET, c2=_UNSET, S_t=_UNSET,
                 friction_N: float = 0.0, bulk_law: str = "gholizadeh", name: str = "", *,
                 c1_factor: float = 1.0, c2_factor: float = 1.0, S_t_factor: float = 1.0,
                 c1_explicit: float | None = None, c2_explicit: float | None = None,
                 S_t_explicit: float | None = None) -> None:
        def put(key, value):
            object.__setattr__(self, key, value)

        for fname, value, unit in (
            ("mu", mu, "Pa s"),
            ("rho_l", rho_l, "kg/m^3"),
            ("B_l", B_l, "Pa"),
            ("V01", V01, "m^3"),
            ("V02", V02, "m^3"),
            ("A_p", A_p, "m^2"),
            ("A_t", A_t, "m^2"),
            ("l_t", l_t, "m"),
            ("p0", p0, "Pa"),
        ):
            put(fname, check_positive(fname, value, unit))
        put("n", check_in_range("n", n, 1.0, 1.67, "-"))
        put("inv_gamma1", check_nonnegative("inv_gamma1", inv_gamma1, "-"))
        put("inv_gamma2", check_nonnegative("inv_gamma2", inv_gamma2, "-"))
        factors = {"c1": c1_factor, "c2": c2_factor, "S_t": S_t_factor}
        stored = {"c1": c1_explicit, "c2": c2_explicit, "S_t": S_t_explicit}
        given = {"c1": c1, "c2": c2, "S_t": S_t}
        for key, unit in DERIVABLE.items():
            put(f"{key}_factor", check_nonnegative(f"{key}_factor", factors[key], "-"))
            value = stored[key] if given[key] is _UNSET else given[key]
            put(f"{key}_explicit", None if value is None else check_nonnegative(key, value, unit))
        if self.c1 == 0.0 and self.c2 == 0.0:
            raise ParameterError(
                "c1 and c2 are both 0: the channel has no resistance; "
                "at least one must be > 0 [kg m^-4 s^-1], [kg m^-7]"
            )
        put("friction_N", check_nonnegative("friction_N", friction_N, "N"))
        put("bulk_law", check_choice("bulk_law", bulk_law, BULK_LAWS))
        if not isinstance(name, str):
            raise ParameterError(f"name must be a str, got {type(name).__name__} {name!r}")
        put("name", name)

    # ----- channel coefficients: derived unless explicit ---------------
    @property
    def c1(self) -> float:
        """Linear loss coefficient c1 [kg m^-4 s^-1]: explicit, or c1_factor 8 pi mu l_t / A_t^2."""
        if self.c1_explicit is not None:
            return self.c1_explicit
        return self.c1_factor * initial_c1(self.mu, self.l_t, self.A_t)

    @property
    def c2(self) -> float:
        """Quadratic loss coefficient c2 [kg m^-7]: explicit, or c2_factor rho_l/(2 C_De^2 A_t^2).
        """
        if self.c2_explicit is not None:
            return self.c2_explicit
        return self.c2_factor * initial_c2(self.rho_l, self.A_t)

    @property
    def S_t(self) -> float:
        """Channel inertance factor S_t [1/m]: explicit, or S_t_factor l_t / A_t."""
        if self.S_t_explicit is not None:
            return self.S_t_explicit
        return self.S_t_factor * initial_S_t(self.l_t, self.A_t)

    @property
    def explicit(self) -> tuple[str, ...]:
        """Names of the channel quantities given as absolute values (``c1``, ``c2``, ``S_t``).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> preset("reference").explicit, preset("reference").replace(S_t=1e5).explicit
        ((), ('S_t',))
        """
        return tuple(k for k in DERIVABLE if getattr(self, f"{k}_explicit") is not None)

    def unused(self) -> dict[str, str]:
        """Inputs that enter no answer because a derived quantity is given explicitly.

        Returns
        -------
        dict
            ``{name: reason}`` in field order; empty when every input is used.
            A geometry input (``mu``, ``l_t``, ``A_t``) is listed when every
            quantity it derives is explicit; a factor when it is not 1 beside
            an explicit value.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> preset("reference").unused()
        {}
        >>> p = preset("paper_initial").replace(c1=1e9, c2=1e14, S_t=2e5)
        >>> list(p.unused())
        ['mu', 'A_t', 'l_t']
        >>> p.unused()["mu"]
        'c1 is given explicitly; mu enters only c1 = c1_factor 8 pi mu l_t / A_t^2'
        """
        explicit = self.explicit
        out = {}
        for source in ("mu", "A_t", "l_t"):
            uses = [k for k, srcs in _SOURCES.items() if source in srcs]
            if all(k in explicit for k in uses):
                given = ", ".join(uses[:-1]) + (" and " if len(uses) > 1 else "") + uses[-1]
                verb = "is" if len(uses) == 1 else "are"
                formulas = " and ".join(_FORMULA[k] for k in uses)
                out[source] = f"{given} {verb} given explicitly; {source} enters only {formulas}"
        for k in explicit:
            if getattr(self, f"{k}_factor") != 1.0:
                out[f"{k}_factor"] = (f"{k} is given explicitly; {k}_factor multiplies only "
                                      f"the geometric estimate ({_FORMULA[k]})")
        return out

    # ----- convenience -------------------------------------------------
    def replace(self, **changes) -> DeviceParams:
        """Return a validated copy with ``changes`` applied (see dataclasses.replace).

        ``c1=``, ``c2=``, ``S_t=`` set explicit values (None: derive again).

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> preset("reference").replace(friction_N=30.0).friction_N
        30.0
        """
        return dataclasses.replace(self, **changes)

    def scaled(self, **multipliers: float) -> DeviceParams:
        """Return a copy with named inputs multiplied, e.g. ``scaled(c1=3.56)``.

        ``c1``, ``c2``, ``S_t`` multiply their factor when derived and their
        value when explicit; ``mu``, ``l_t``, ``A_t`` change the derived
        coefficients they enter.

        Raises
        ------
        ParameterError
            For a name outside :data:`SCALABLE`, a negative multiplier, or a
            multiplier other than 1 on an input :meth:`unused` lists.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> p = preset("paper_initial")
        >>> p.scaled(c1=2.0).c1 / p.c1
        2.0
        >>> q = p.scaled(l_t=2.0)                  # longer channel: c1 and S_t double
        >>> round(q.c1 / p.c1, 12), round(q.S_t / p.S_t, 12), q.c2 == p.c2
        (2.0, 2.0, True)
        """
        changes = {}
        unused = self.unused()
        for key, factor in multipliers.items():
            if key not in SCALABLE:
                raise ParameterError(
                    f"cannot scale {key!r}; scalable parameters: {', '.join(SCALABLE)}"
                )
            factor = check_nonnegative(f"multiplier of {key}", factor)
            if key in DERIVABLE:
                explicit = getattr(self, f"{key}_explicit")
                if explicit is None:
                    changes[f"{key}_factor"] = getattr(self, f"{key}_factor") * factor
                else:
                    changes[key] = explicit * factor
                continue
            if key in unused and factor != 1.0:
                raise ParameterError(
                    f"cannot scale {key} by {factor:g}: it is unused ({unused[key]}); "
                    f"scale the explicit value or set it to None to derive it"
                )
            changes[key] = getattr(self, key) * factor
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

    def derived(self) -> dict:
        """All parameters and derived quantities as ``{"name [unit]": value}``.

        Every value is a float, except that when an input is unused (an
        explicit c1, c2 or S_t displaces it) key ``"unused"`` holds
        :meth:`unused` (name -> reason); it is absent when every input is used,
        so the float-only table of a fully derived set is unchanged.

        Examples
        --------
        >>> from liquidamp.device import preset
        >>> d = preset("paper_initial").derived()
        >>> f"{d['c1 [kg m^-4 s^-1]']:.4e}", round(d["b_L [kg]"], 1), "unused" in d
        ('1.0485e+09', 89.4, False)
        >>> list(preset("reference").replace(c1=1e9).derived()["unused"])
        ['mu', 'c1_factor']
        """
        unused = self.unused()
        out = {
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
            "c1_factor [-]": self.c1_factor,
            "c2_factor [-]": self.c2_factor,
            "S_t_factor [-]": self.S_t_factor,
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
        if unused:
            out["unused"] = unused
        return out


#: Inputs :meth:`DeviceParams.scaled` may multiply (and calibration may vary; ``p0``, the
#: filling pressure, is the chambers' pressure level: freed by the diagnosis's
#: ``pressure_level`` refinement).
SCALABLE = ("mu", "rho_l", "B_l", "V01", "V02", "A_p", "A_t", "l_t", "inv_gamma1", "inv_gamma2",
            "c1", "c2", "S_t", "friction_N", "p0")

#: Keyword inputs of :class:`DeviceParams` in their public form (device-file keys):
#: every field except the stored ``*_explicit`` forms, which are given as ``c1``, ``c2``, ``S_t``.
INPUT_NAMES = ("mu", "rho_l", "B_l", "V01", "V02", "A_p", "A_t", "l_t", "p0", "n",
               "inv_gamma1", "inv_gamma2", "c1", "c2", "S_t", "c1_factor", "c2_factor",
               "S_t_factor", "friction_N", "bulk_law", "name")
