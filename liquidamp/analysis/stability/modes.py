"""Modal properties and mode tracking across a parameter sweep.

Eigenvalues of a sweep (rotor speed, airspeed) come out of the eigensolver in
no particular order.  :func:`track_modes` orders them so that column ``j``
follows one physical mode: consecutive steps are matched by the Hungarian
algorithm (:func:`scipy.optimize.linear_sum_assignment`) on a cost made of
the modal assurance criterion (MAC) of the eigenvectors and the distance
between eigenvalues.

References
----------
.. [1] R. J. Allemang, D. L. Brown, "A correlation coefficient for modal
   vector analysis", Proc. 1st IMAC, 1982 (the MAC).
.. [2] H. W. Kuhn, "The Hungarian method for the assignment problem", Naval
   Research Logistics Quarterly 2, 83-97, 1955.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from liquidamp.errors import ParameterError

__all__ = ["mac", "track_modes", "TrackedModes", "damping_ratio"]


def mac(phi_a: np.ndarray, phi_b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between the columns of two mode-shape matrices.

    Parameters
    ----------
    phi_a, phi_b : ndarray, shape (n, ma) and (n, mb)
        Complex mode shapes as columns.

    Returns
    -------
    ndarray, shape (ma, mb)
        ``|phi_a^H phi_b|^2 / ((phi_a^H phi_a)(phi_b^H phi_b))`` in [0, 1].

    Examples
    --------
    >>> phi = np.array([[1.0, 0.0], [0.0, 1.0]])
    >>> mac(phi, phi).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    a = np.asarray(phi_a, dtype=complex)
    b = np.asarray(phi_b, dtype=complex)
    num = np.abs(a.conj().T @ b) ** 2
    na = np.real(np.sum(a.conj() * a, axis=0))
    nb = np.real(np.sum(b.conj() * b, axis=0))
    den = np.outer(na, nb)
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0.0)


def damping_ratio(eigenvalues) -> np.ndarray:
    """Damping ratio ``-Re(lambda)/|lambda|`` [-] (1 for a zero eigenvalue).

    Examples
    --------
    >>> float(damping_ratio(-0.1 + 1j * np.sqrt(0.99)))
    0.1
    """
    lam = np.asarray(eigenvalues, dtype=complex)
    mag = np.abs(lam)
    safe = np.where(mag > 0.0, mag, 1.0)
    return np.where(mag > 0.0, -lam.real / safe, 1.0)


@dataclass(frozen=True, eq=False)
class TrackedModes:
    """Eigenvalues of a sweep ordered so that each column is one mode.

    Attributes
    ----------
    parameter : ndarray, shape (n_steps,)
        The swept parameter (unit of the caller, e.g. [rad/s]).
    eigenvalues : ndarray, shape (n_steps, n_modes)
        Tracked eigenvalues [1/s or nondimensional].
    vectors : ndarray or None, shape (n_steps, n, n_modes)
        Tracked eigenvectors, if given.
    """

    parameter: np.ndarray
    eigenvalues: np.ndarray
    vectors: np.ndarray | None = None

    @property
    def n_modes(self) -> int:
        """Number of tracked modes [-]."""
        return self.eigenvalues.shape[1]


def track_modes(parameter, eigenvalues, vectors=None, *, weight: float = 1.0) -> TrackedModes:
    """Order eigenvalues (and vectors) of a sweep mode by mode.

    Parameters
    ----------
    parameter : array, shape (n_steps,)
        Swept parameter.
    eigenvalues : array, shape (n_steps, n_modes)
        Eigenvalues at each step, any order.
    vectors : array, shape (n_steps, n, n_modes), optional
        Eigenvectors as columns; without them only eigenvalue distances count.
    weight : float
        Weight of the eigenvalue distance (relative to the mean modulus)
        against ``1 - MAC`` in the assignment cost [-].

    Returns
    -------
    TrackedModes

    Examples
    --------
    >>> lam = np.array([[1.0, 2.0], [2.1, 1.1], [1.2, 2.2]])
    >>> track_modes([0, 1, 2], lam).eigenvalues.real.tolist()
    [[1.0, 2.0], [1.1, 2.1], [1.2, 2.2]]
    """
    p = np.asarray(parameter, dtype=float)
    lam = np.array(eigenvalues, dtype=complex)
    if lam.ndim != 2 or lam.shape[0] != p.size:
        raise ParameterError(
            f"eigenvalues must have shape (n_steps={p.size}, n_modes), got {lam.shape}"
        )
    vec = None if vectors is None else np.array(vectors, dtype=complex)
    out = lam.copy()
    outv = None if vec is None else vec.copy()
    for i in range(1, p.size):
        prev = out[i - 1]
        scale = max(float(np.mean(np.abs(prev))), 1e-12)
        cost = weight * np.abs(prev[:, None] - lam[i][None, :]) / scale
        if vec is not None:
            cost = cost + (1.0 - mac(outv[i - 1], vec[i]))
        rows, cols = linear_sum_assignment(cost)
        order = cols[np.argsort(rows)]
        out[i] = lam[i][order]
        if vec is not None:
            outv[i] = vec[i][:, order]
    return TrackedModes(p, out, outv)
