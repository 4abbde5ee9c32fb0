"""The order of a diagnosis round's fits (diagnosis._fit_round, module doc step 4): the
second wave's first fit comes before any restart, and restarts are made only where no refit
of the round (both waves) reaches the structure level.  The refits are stand-ins recorded in
call order (no model runs; well under a second)."""

import types

import numpy as np
import pytest

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.measured.diagnosis_evidence import Candidate
from liquidamp.analysis.measured.diagnosis_options import DiagnoseOptions
from liquidamp.analysis.measured.records import Record


def _round(monkeypatch, fitted_nrmse, restarted_nrmse, n_free=None, noise=1e-4,
           names="abc", heldout=None, floors=None):
    calls = []
    heldout = heldout or {}

    def refit(cand, *a, **k):
        calls.append(("refit", cand.effect))
        errors = tuple(types.SimpleNamespace(role="validation", label=label, nrmse=v)
                       for label, v in heldout.get(cand.effect, {}).items())
        return types.SimpleNamespace(nrmse_calibration=fitted_nrmse[cand.effect],
                                     effect=cand.effect, record_errors=errors)

    def restart(res, *a, **k):
        assert a[-1] is not None  # the joint reaches every restart
        calls.append(("restart", res.effect))
        return types.SimpleNamespace(nrmse_calibration=restarted_nrmse[res.effect],
                                     effect=res.effect)

    monkeypatch.setattr(D, "_refit", refit)
    monkeypatch.setattr(D, "_restart", restart)
    t = np.arange(0.0, 2.0, 0.005)
    rec = Record.from_arrays(t, 3e-3 * np.sin(6 * np.pi * t), 500 * np.sin(6 * np.pi * t))
    current = types.SimpleNamespace(calibration=(rec,))
    a, b, c = (Candidate(n, s, 0.0, {}) for n, s in zip(names, (0.9, 0.8, 0.5), strict=True))
    cfg = DiagnoseOptions()
    n_free = n_free or dict.fromkeys(names, 1)
    probes = {k: types.SimpleNamespace(free=(("x", "y"),) * n, multipliers=())
              for k, n in n_free.items()}
    ranked = [a, b, c]
    joint = object()  # the device multipliers a restart frees beside the effect
    refits, beside = D._fit_round(ranked, probes, [a, b], [c], current, (), None,
                                  cfg.budget, level=0.01, start0={}, sel=cfg.selection,
                                  noise=noise, joint=joint, floors=floors)
    # the round hands its joint on to the reductions' refits only where it restarted
    assert beside is (joint if any(w == "restart" for w, _ in calls) else None)
    return calls, {k: v.nrmse_calibration for k, v in refits.items()}, ranked


def test_the_next_candidate_is_fitted_before_any_restart(monkeypatch):
    # the third candidate reaches the level at once: nothing is restarted
    calls, got, _ = _round(monkeypatch, {"a": 0.05, "b": 0.04, "c": 0.005},
                        {"a": 0.001, "b": 0.001, "c": 0.001})
    assert calls == [("refit", "a"), ("refit", "b"), ("refit", "c")]
    assert got == {"a": 0.05, "b": 0.04, "c": 0.005}


@pytest.mark.parametrize(("restarted", "expected"), [
    # no restart reaches the level: every refit of the round is restarted, in order
    ({"a": 0.03, "b": 0.02, "c": 0.02}, ["a", "b", "c"]),
    # the first restart reaches it: the others are not restarted
    ({"a": 0.005, "b": 0.02, "c": 0.02}, ["a"])])
def test_restarts_only_where_no_refit_of_the_round_reaches_the_level(monkeypatch, restarted,
                                                                      expected):
    calls, got, _ = _round(monkeypatch, {"a": 0.05, "b": 0.04, "c": 0.03}, restarted)
    assert calls[:3] == [("refit", "a"), ("refit", "b"), ("refit", "c")]
    assert [n for what, n in calls[3:] if what == "restart"] == expected
    assert got[expected[-1]] == restarted[expected[-1]]


def test_a_first_wave_at_the_level_leaves_the_next_candidate_unfitted(monkeypatch):
    calls, got, _ = _round(monkeypatch, {"a": 0.005, "b": 0.04, "c": 0.03}, {})
    assert calls == [("refit", "a"), ("refit", "b")]
    assert set(got) == {"a", "b"}


@pytest.mark.parametrize(("n_free", "fitted", "quiet"), [
    # a (1 parameter) at the noise: b frees more and is not refitted, c (as many) is
    ({"a": 1, "b": 3, "c": 1}, ["a", "c"], "a"),
    # a frees the most: b, simpler, is still refitted, reaches the noise too and then
    # holds c (2 parameters) back
    ({"a": 3, "b": 1, "c": 2}, ["a", "b"], "b"),
    ({"a": 3, "b": 3, "c": 2}, ["a", "b", "c"], None)])
def test_a_refit_at_the_noise_leaves_richer_candidates_unfitted(monkeypatch, n_free, fitted,
                                                                quiet):
    """Parsimony at the noise: once a refit leaves the residual at the noise (here 0.008 <=
    0.01), a later candidate freeing more parameters could only tie on noise and lose on the
    BIC; it is not refitted, and its note says which candidate and why.  The second wave is
    not reached (the first explains the round), so c is in the first here."""
    monkeypatch.setattr(D, "_explained", lambda *a: False)
    calls, got, ranked = _round(monkeypatch, {"a": 0.008, "b": 0.009, "c": 0.02},
                                dict.fromkeys("abc", 0.02), n_free=n_free, noise=0.01)
    assert [n for what, n in calls if what == "refit"] == fitted
    skipped = [c for c in ranked if c.effect not in fitted]
    assert all(c.note.startswith(f"not refitted: {quiet} already leaves the residual at "
                                 "the noise") for c in skipped)


@pytest.mark.parametrize("error", ["ParameterError", "PressureError", "ConvergenceError"])
def test_a_restart_whose_model_fails_keeps_the_refit(monkeypatch, error):
    """A restart whose model or fit fails (a parameter out of its model's range from the
    physics start, a chamber at the pressure floor, no convergence) is that start's failure,
    as a refit's is: the refit is kept and the round goes on (a ParameterError ended the
    whole diagnosis before)."""
    import liquidamp.analysis.measured.diagnosis_fits as F
    import liquidamp.errors as E

    def calibrate(*a, **k):
        raise getattr(E, error)("stand-in: the restart's model failed")

    monkeypatch.setattr(F, "calibrate", calibrate)
    spec = types.SimpleNamespace(parameters=(), with_values=lambda values: spec)
    res = types.SimpleNamespace(spec=spec, at_bounds=lambda: (), effects=(), cost=1.0)
    current = types.SimpleNamespace(calibration=(), model="full", start_params=None)
    assert F._restart(res, current, (), None, 0.0, 10, 1e-8, {}, "auto", 0.02) is res


def test_nested_candidates_are_fitted_simplest_first_and_the_richer_left_at_the_noise(
        monkeypatch):
    """Nested hypotheses from the smallest up: a leak queued behind the digressive and the
    relief valves it is a limit of (diagnosis_select._simplest_first) is refitted first; at
    the noise it leaves both valves, which free more parameters, unfitted (the quiet rule).
    Before, the digressive valve (8 free parameters) was fitted first: 1.6 s of the 200 Hz
    leakage bench record's 3.4 s.  Where the leak stays above the noise the valves follow,
    the simpler one first."""
    names = ("digressive_valve", "relief_valve", "leakage")
    n_free = {"digressive_valve": 4, "relief_valve": 2, "leakage": 1}
    monkeypatch.setattr(D, "_explained", lambda *a: False)
    calls, got, ranked = _round(monkeypatch, {"digressive_valve": 0.009, "relief_valve": 0.009,
                                              "leakage": 0.008},
                                dict.fromkeys(names, 0.02), n_free=n_free, noise=0.01,
                                names=names)
    assert [n for what, n in calls if what == "refit"] == ["leakage"]
    assert all(c.note.startswith("not refitted: leakage already leaves the residual at the "
                                 "noise") for c in ranked if c.effect != "leakage")
    calls, got, ranked = _round(monkeypatch, {"digressive_valve": 0.009, "relief_valve": 0.009,
                                              "leakage": 0.02},
                                dict.fromkeys(names, 0.02), n_free=n_free, noise=0.01,
                                names=names)
    assert [n for what, n in calls if what == "refit"] == ["leakage", "relief_valve"]


def test_no_reduction_of_a_refit_above_the_noise_once_another_refit_is_at_it(monkeypatch):
    """diagnosis_select._bounded_reductions: a reduction (backlash -> its friction alone) is
    a limit of its richer model, so its calibration residual cannot come below that refit's;
    where another refit of the round is already at the noise and the richer one is above it,
    the reduction is not refitted (200 Hz elastomer bench record: 0.46 s of 3.3 s).  With no
    refit at the noise it is refitted as before."""
    import liquidamp.analysis.measured.diagnosis_select as S

    calls = []

    def link(cand, *a, **k):
        calls.append(cand.effect)
        return types.SimpleNamespace(nrmse_calibration=0.05), None

    monkeypatch.setattr(S, "_refit_link", link)
    monkeypatch.setattr(S, "_judge_round", lambda ranked, new, *a: ranked)
    sel = DiagnoseOptions().selection
    names = ("elastomer", "backlash", "smooth_friction")
    probes = dict.fromkeys(names, object())

    def reductions(elastomer_nrmse):
        calls.clear()
        ranked = [Candidate("elastomer", 0.9, 0.0, {}, accepted=True),
                  Candidate("backlash", 0.6, 0.0, {}, accepted=True),
                  Candidate("smooth_friction", 0.2, 0.0, {})]
        refits = {"elastomer": types.SimpleNamespace(nrmse_calibration=elastomer_nrmse),
                  "backlash": types.SimpleNamespace(nrmse_calibration=0.03)}
        S._bounded_reductions(ranked, refits, probes, None, (), None, None, sel, None,
                              noise=0.01)
        return list(calls)

    assert reductions(0.004) == []
    assert reductions(0.02) == ["smooth_friction"]


@pytest.mark.parametrize(("heldout", "fitted"), [
    # a at the noise on calibration and on both held-out records: b, as many parameters,
    # could at best tie everywhere and is not refitted; c, fewer, is
    ({"v1": 0.004, "v2": 0.009}, ["a", "c"]),
    # one held-out record above its noise: b may still predict it better, so it is refitted
    ({"v1": 0.004, "v2": 0.011}, ["a", "b", "c"])])
def test_a_refit_at_the_noise_on_every_record_leaves_as_rich_candidates_unfitted(
        monkeypatch, heldout, fitted):
    """The quiet rule for a candidate freeing as many parameters (diagnosis_select.
    _held_back): held back only where the refit at the noise also predicts every held-out
    record within noise_factor x its own floor (here 0.01 each)."""
    monkeypatch.setattr(D, "_explained", lambda *a: False)
    calls, got, ranked = _round(monkeypatch, {"a": 0.008, "b": 0.009, "c": 0.02},
                                dict.fromkeys("abc", 0.02), n_free={"a": 2, "b": 2, "c": 1},
                                noise=0.01, heldout={"a": heldout},
                                floors={"v1": 0.01 / 1.5, "v2": 0.01 / 1.5})
    assert [n for what, n in calls if what == "refit"] == fitted
    if "b" not in fitted:
        b = next(c for c in ranked if c.effect == "b")
        assert b.note.startswith("not refitted: a already leaves the residual at the noise, "
                                 "and every held-out record at its own")


def test_a_round_at_the_calibration_level_is_not_explained_while_a_heldout_record_is_far_off(
        monkeypatch):
    """diagnosis_select._explained with the held-out floors: a refit at the calibration
    level that leaves a held-out record above structure_factor x its floor does not end the
    round; the second wave is fitted (R_leakage3: the leak, scored low because c1 absorbs
    its signature, waited there behind a Coulomb friction at the calibration level and 27 x
    the held-out floor).  Where the held-out record is at its floor too, the round ends as
    before."""
    far = _round(monkeypatch, {"a": 0.005, "b": 0.04, "c": 0.03},
                 dict.fromkeys("abc", 0.02), heldout={"a": {"v": 0.05}},
                 floors={"v": 0.002})[0]
    assert [n for what, n in far if what == "refit"] == ["a", "b", "c"]
    near = _round(monkeypatch, {"a": 0.005, "b": 0.04, "c": 0.03},
                  dict.fromkeys("abc", 0.02), heldout={"a": {"v": 0.003}},
                  floors={"v": 0.002})[0]
    assert near == [("refit", "a"), ("refit", "b")]
