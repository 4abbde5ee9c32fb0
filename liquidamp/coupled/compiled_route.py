"""Whether the compiled kernels can run a coupled system (:func:`compiled_support`).

Between the systems (:mod:`liquidamp.coupled.system`) and the compiled kernels
(:mod:`liquidamp.coupled.fast`) below, and the engines
(:mod:`liquidamp.coupled.engines`) and the time domain
(:mod:`liquidamp.coupled.assembly`, which re-exports :func:`compiled_support`)
above.
"""

from __future__ import annotations

from liquidamp.coupled.fast import check_compiled
from liquidamp.coupled.system import (  # noqa: F401 (names of the doctest)
    CoupledSystem,
    Device,
    _compiled_origin,
    rotor_system,
)
from liquidamp.errors import ParameterError

__all__ = ["compiled_support"]


def compiled_support(system: CoupledSystem) -> str | None:
    """Why ``SolverOptions(engine="compiled")`` cannot run ``system``, or None if it can.

    The compiled route of :func:`simulate_coupled` takes a ground-resonance
    rotor built by :func:`rotor_system` or a blade built by
    :func:`blade_system` (with any external inputs) whose devices do not use
    the stroke acceleration (every model of the family, with any add-on
    effects, and the viscous damper are compiled; a device that reads a measured input
    channel is refused: a coupled host has no channel series); it integrates with DOP853
    and agrees with the Python route run with ``method="DOP853"`` to
    round-off (about 1e-13 relative).

    Parameters
    ----------
    system : CoupledSystem
        Host with devices.

    Returns
    -------
    str or None
        The reason, as the ParameterError :func:`simulate_coupled` would raise.

    Examples
    --------
    >>> from liquidamp.structure.hostio import load_rotor
    >>> from liquidamp.device import preset
    >>> rotor = load_rotor("hammond1974")
    >>> compiled_support(rotor_system(rotor, 27.2, Device("full", preset("reference")))) is None
    True
    >>> "acceleration" in compiled_support(rotor_system(rotor, 27.2,
    ...                                                 Device("inerter", preset("inerter"))))
    True
    """
    for d in getattr(system, "devices", ()):
        if getattr(d.model, "input_channels", ()):
            # a coupled host carries no measured channel series (issue #20)
            from liquidamp.device.effects_base import check_input_channels

            try:
                check_input_channels(d.model, (), f"the coupled system {system.name!r}")
            except ParameterError as exc:
                return str(exc)
    try:
        _compiled_origin(system, check_compiled)
    except ParameterError as exc:
        return str(exc)
    return None
