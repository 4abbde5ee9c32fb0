"""Issue #19 bench: the performance paths of the periodic orbit and the record model.

* A grid of many phases (a 3 kHz record conditioned by decimation and averaging needs the
  model at its 60 000 raw phases) is no longer marched on: the march compares the force
  waveforms on the uniform grid and the states at the fine grid come from one run of the
  final period from its start (``periodic.FINE_GRID_FACTOR``).  Two routes to the same
  states: the fine grid marched on (the factor raised) and the new route, within the
  integration error of the fit options (measured: 5e-8 of the force, 2e-7 with freeplay).
* A warm start of a model with vapour cavities is projected onto all three invariants of
  rest, like any other: the chamber rows count the liquid in the chamber less its cavity,
  which the cavity equations conserve exactly (session 10; before, only the total mass was
  conserved, and a warm start kept its own chamber rows).

Cost (warm, idle machine): about 2 s.
"""

import numpy as np
import pytest

from liquidamp.coupled import invariants as invariants_mod
from liquidamp.coupled import periodic
from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.invariants import onto_invariants
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.options import PRESETS
from liquidamp.structure.testmachine import HarmonicStroke


@pytest.mark.parametrize("effects", [(), (("coulomb_friction", {"force_N": 30.0}),)])
def test_fine_grid_from_the_final_period_matches_the_march_on_it(monkeypatch, effects):
    p = preset("paper_calibrated")
    m = with_effects(get_model("full"), *(make_effect(n, **kw) for n, kw in effects))
    options = PRESETS["fit"]
    stroke = HarmonicStroke(0.003, 3.0)
    rig = TestRig(m, p, stroke)
    engine = engine_for(rig, options)
    T = stroke.period
    # 5000 irregular phases (more than FINE_GRID_FACTOR x 512), ending at the period's end
    rng = np.random.default_rng(3)
    grid = np.append(np.sort(rng.uniform(0.0, T, 5000)), T)
    x0 = m.initial_state(p, 0.0)
    new = periodic.periodic_state(rig, engine, x0, options, grid=grid)
    monkeypatch.setattr(periodic, "FINE_GRID_FACTOR", 10 ** 9)
    old = periodic.periodic_state(rig, engine, x0, options, grid=grid)
    assert new.states.shape == old.states.shape == (m.n_states, grid.size - 1)
    assert new.route == old.route == "march" and new.cycles == old.cycles
    f_new = m.force(grid[:-1], new.states, stroke(grid[:-1]), p)
    f_old = m.force(grid[:-1], old.states, stroke(grid[:-1]), p)
    err = np.max(np.abs(f_new - f_old)) / np.max(np.abs(f_old))
    assert err < 1e-5  # the fit options' rtol 1e-6, over one period
    # a different route, not a copy: the run of the final period starts afresh
    assert err > 0.0


def test_cavitation_warm_start_is_projected_onto_the_invariants_of_rest():
    p = preset("paper_calibrated")
    plain = get_model("full")
    cav = with_effects(plain, make_effect("cavitation", vapour_pressure_Pa=5e4))
    for m in (plain, cav):
        rest = m.initial_state(p, 0.0)
        x = rest.copy()
        x[1] *= 0.95  # chamber 1's density 5 % off its pressure curve, the mass changed
        out = onto_invariants(m, p, x, rest, 0.0)
        v, _ = invariants_mod.invariants(m, p, out, 0.0)
        v_rest, _ = invariants_mod.invariants(m, p, rest, 0.0)
        assert v[2] == pytest.approx(v_rest[2], rel=1e-12)  # the mass of rest
        assert v[0] == pytest.approx(1.0, abs=1e-12)  # the chamber curves of rest restored
        assert v[1] == pytest.approx(1.0, abs=1e-12)
    # an open cavity with the liquid on its curve, rho1 V1 = r1(p_v) (V1 - Vc1), sits on the
    # chamber level set of rest: the row counts the liquid, not the chamber
    x = cav.initial_state(p, 0.0)
    r_v, _ = invariants_mod._chamber_density(5e4, 1, p)
    x[0], x[5] = 5e4, 0.01 * p.V01
    x[1] = r_v * 0.99
    v, G = invariants_mod.invariants(cav, p, x, 0.0)
    assert v[0] == pytest.approx(1.0, abs=1e-12)
    # the gradient against central differences (the cavity column is new)
    h = np.array(cav.state_scales(p)) * 1e-6
    for k in (0, 1, 5):
        e = np.zeros(x.size)
        e[k] = h[k]
        fd = (invariants_mod.invariants(cav, p, x + e, 0.0)[0]
              - invariants_mod.invariants(cav, p, x - e, 0.0)[0]) / (2 * h[k])
        assert np.allclose(G[:, k], fd, rtol=1e-6, atol=1e-9 * np.abs(G[:, k]).max()), k
    # behind a dead band with a cavity open: every column, the piston's included (the
    # chamber rows then move with the piston's stroke through V / (V - Vc))
    both = with_effects(plain, make_effect("cavitation", vapour_pressure_Pa=5e4),
                        make_effect("freeplay", gap_m=1e-4))
    names = both.state_names
    x = both.initial_state(p, 0.0)
    x[names.index("p1")], x[names.index("Vc1")] = 5e4, 0.01 * p.V01
    x[names.index("rho1")] = r_v * 0.99
    x[names.index("y_fp")] = 0.7e-4
    v, G = invariants_mod.invariants(both, p, x, 0.0)
    assert G[0, names.index("y_fp")] != 0.0
    h = np.array(both.state_scales(p)) * 1e-6
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = h[k]
        fd = (invariants_mod.invariants(both, p, x + e, 0.0)[0]
              - invariants_mod.invariants(both, p, x - e, 0.0)[0]) / (2 * h[k])
        assert np.allclose(G[:, k], fd, rtol=1e-6, atol=1e-9 * np.abs(G).max()), names[k]
