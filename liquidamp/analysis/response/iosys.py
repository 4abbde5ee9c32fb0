"""Device models as python-control nonlinear I/O systems.

:func:`to_iosys` wraps any registered model of
:mod:`liquidamp.device.models` as a :class:`control.NonlinearIOSystem` with
named signals, so that python-control users can ``interconnect`` it with a
host, ``linearize`` it and run ``input_output_response``:

* inputs ``'stroke'`` [m], ``'stroke_rate'`` [m/s], ``'stroke_acceleration'``
  [m/s^2] -- the model's u = (y, v, a); the host supplies all three (the
  stroke-only models simply ignore the rest);
* outputs ``'force'`` [N] (load-cell force, friction included) and, where the
  model has chamber pressures, ``'p1'``, ``'p2'`` [Pa] (absolute);
* states named by ``model.state_names`` (units ``model.state_units``).

The python-control ``params`` dictionary is not used: the device parameters
are fixed when the system is built (a frozen :class:`DeviceParams`), so no
hidden mutable state changes an answer.  ``control.linearize(sys, x0, u0)``
then agrees with :func:`liquidamp.analysis.response.linear.linearize` (without
friction, which has no small-signal linearization).

References
----------
.. [1] B. Titurus, AIAA J. 56(10), 2018, eqs. (10)-(20).
"""

from __future__ import annotations

import control
import numpy as np

from liquidamp.analysis.response.linear import INPUT_NAMES
from liquidamp.device.models import get_model
from liquidamp.device.params import DeviceParams
from liquidamp.errors import ParameterError

__all__ = ["to_iosys"]


def to_iosys(model, params: DeviceParams, *, name: str | None = None,
             pressures: bool = True) -> control.NonlinearIOSystem:
    """A registered device model as a :class:`control.NonlinearIOSystem`.

    Parameters
    ----------
    model : str or DeviceModel
        Registered model name.
    params : DeviceParams
        Device parameters (frozen into the system).
    name : str, optional
        System name (default ``"device_<model>"``).
    pressures : bool
        Include ``'p1'``, ``'p2'`` outputs where the model has chamber
        pressures (default True).

    Returns
    -------
    control.NonlinearIOSystem
        Continuous-time; inputs :data:`~liquidamp.analysis.response.linear.INPUT_NAMES`.

    Examples
    --------
    >>> from liquidamp.device import preset
    >>> sys = to_iosys("full", preset("reference"))
    >>> sys.input_labels
    ['stroke', 'stroke_rate', 'stroke_acceleration']
    >>> sys.output_labels, sys.state_labels
    (['force', 'p1', 'p2'], ['p1', 'rho1', 'p2', 'rho2', 'm12'])
    """
    m = get_model(model)
    if not isinstance(params, DeviceParams):
        raise ParameterError(f"params must be DeviceParams, got {type(params).__name__}")
    m.check_params(params)
    p = params
    with_p = pressures and m.pressures is not None
    outputs = ["force", "p1", "p2"] if with_p else ["force"]

    def updfcn(t, x, u, _params=None):
        return np.asarray(m.rhs(t, np.asarray(x, float), tuple(np.asarray(u, float)), p), float)

    def outfcn(t, x, u, _params=None):
        x = np.asarray(x, float)
        uu = tuple(np.asarray(u, float))
        out = [float(m.force(t, x, uu, p))]
        if with_p:
            p1, p2 = m.pressures(x, uu, p)
            out += [float(p1), float(p2)]
        return np.array(out)

    return control.NonlinearIOSystem(
        updfcn if m.n_states else None, outfcn, inputs=list(INPUT_NAMES), outputs=outputs,
        states=list(m.state_names) if m.n_states else None, name=name or f"device_{m.name}",
        dt=0)
