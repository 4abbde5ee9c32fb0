"""Friction behind its own dead band, the fluid on the rod (``Freeplay(drives="friction")``).

A fluid device whose piston is fixed to the rod beside a friction element (a band, a second
seal) coupled to the rod through play: the fluid sees the rod stroke, only the friction at
``location="piston"`` sees the dead band's output.  Checks:

* the fluid's equations are the bare model's at the rod stroke, whatever the dead band's
  state (the old composition put the fluid behind every dead band);
* under y = A sin(w t) the load cell reads the bare fluid's steady force plus Coulomb
  friction that is off while the rod crosses the gap, so the energy per cycle is the bare
  fluid's plus 2 F_c (2A - 2g) (closed form, as for the friction damper's dead band);
* a dead band that drives nothing is refused.
"""

import numpy as np
import pytest

from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import CoulombFriction, Freeplay, SmoothFriction, with_effects
from liquidamp.device.models import get_model
from liquidamp.errors import ParameterError
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke

A, G, FC, F_HZ = 2e-3, 4e-4, 40.0, 2.0
P = preset("reference")


def _work(r):
    """Energy dissipated per cycle, the integral of F v dt over one period [J]."""
    return float(np.sum(r.force * r.stroke_rate)) / (F_HZ * r.time.size)


def test_fluid_sees_the_rod_and_only_the_friction_sees_the_gap():
    bare = get_model("full")
    own = with_effects(bare, Freeplay(G, drives="friction"),
                       SmoothFriction(FC, 1e6, location="piston"))
    behind = with_effects(bare, Freeplay(G), SmoothFriction(FC, 1e6, location="piston"))
    x0 = bare.initial_state(P, 0.0)
    xb = x0 * np.array([1.3, 1.0 + 1e-4, 0.8, 1.0 - 1e-4, 1.0]) + np.array([0, 0, 0, 0, 1e-5])
    y, v = 1e-3, 0.02
    ref = bare.rhs(0.0, xb, (y, v, 0.0), P)
    for y_fp in (y - G, y - 0.5 * G, y + 3 * G):  # in contact, in the gap, far off
        x = np.concatenate([xb, [y_fp, 0.3]])
        np.testing.assert_allclose(own.rhs(0.0, x, (y, v, 0.0), P)[:5], ref, rtol=1e-12)
        f_own = own.force(0.0, x, (y, v, 0.0), P)
        f_bare = bare.force(0.0, xb, (y, v, 0.0), P)
        assert float(f_own - f_bare) == pytest.approx(0.3 * FC, rel=1e-9)
    # behind the attachment's dead band (drives="piston") the fluid sees y_fp instead
    x = np.concatenate([xb, [y - 0.5 * G, 0.3]])
    assert not np.allclose(behind.rhs(0.0, x, (y, v, 0.0), P)[:5], ref, rtol=1e-6)


def test_coulomb_behind_its_own_dead_band_adds_2Fc_2A_minus_2g_to_the_fluid_loop():
    opts = SolverOptions(rtol=1e-8)
    s = HarmonicStroke(A, F_HZ)
    r0 = steady_state("full", P, s, options=opts)
    m = with_effects(get_model("full"), Freeplay(G, drives="friction"),
                     CoulombFriction(FC, location="piston"))
    r1 = steady_state(m, P, s, options=opts)
    assert r0.status == "steady" and r1.status == "steady"
    extra = _work(r1) - _work(r0)
    assert extra == pytest.approx(2 * FC * (2 * A - 2 * G), rel=0.03)
    # the fluid's own loop is unchanged: away from the friction's switching the forces differ
    # by +-F_c or 0 only
    d = np.interp(r0.time, r1.time, r1.force) - r0.force
    near = np.min(np.abs(np.abs(d)[:, None] - np.array([0.0, FC])[None, :]), axis=1)
    assert np.mean(near < 0.02 * FC) > 0.9


def test_a_dead_band_that_drives_only_friction_needs_friction_behind_it():
    with pytest.raises(ParameterError, match="drives='friction' needs friction"):
        with_effects(get_model("full"), Freeplay(G, drives="friction"),
                     CoulombFriction(FC))  # at the rod
    with pytest.raises(ParameterError, match="drives must be one of"):
        Freeplay(G, drives="fluid")
