"""Mode tracking by MAC and the Hungarian assignment."""

import numpy as np

from liquidamp.analysis.stability.modes import damping_ratio, mac, track_modes


def test_tracking_through_a_frequency_crossing():
    # two modes whose frequencies cross; shapes stay distinct -> tracked by MAC
    p = np.linspace(0.0, 2.0, 21)
    lam, vec = [], []
    for x in p:
        w = np.array([1j * (1.0 + 0.5 * x), 1j * 2.0])
        v = np.array([[1.0, 0.1], [0.1, 1.0]])
        order = np.argsort(w.imag) if x < 1.0 else np.argsort(-w.imag)
        lam.append(w[order])
        vec.append(v[:, order])
    tr = track_modes(p, lam, vec)
    assert np.allclose(tr.eigenvalues[:, 1], 2.0j)
    assert np.allclose(tr.eigenvalues[:, 0].imag, 1.0 + 0.5 * p)


def test_mac_and_damping_ratio():
    a = np.array([[1.0], [1j]])
    assert np.isclose(mac(a, a)[0, 0], 1.0)
    assert np.isclose(mac(a, np.array([[1.0], [-1j]]))[0, 0], 0.0)
    assert np.isclose(damping_ratio(-0.05 + 1j * np.sqrt(1 - 0.05**2)), 0.05)
