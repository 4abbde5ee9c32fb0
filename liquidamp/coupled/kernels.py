"""The compiled pieces of :mod:`liquidamp.coupled` that the analyses call directly.

A public face over the private kernel modules (:mod:`liquidamp.coupled._linalg`,
:mod:`liquidamp.coupled._rotor_kernel`), so that no other package imports a
private module: small dense LU factorization with partial pivoting and its solve
(:func:`lu_factor`, :func:`lu_solve`, real or complex; a singular matrix is
reported, never divided by), and the derivatives of a device's rates and force along the stroke
(:func:`device_derivatives`, with its relative difference increment
:data:`FD_REL`).
"""

from liquidamp.coupled._linalg import lu_factor, lu_solve
from liquidamp.coupled._rotor_kernel import FD_REL, device_derivatives

__all__ = ["lu_factor", "lu_solve", "device_derivatives", "FD_REL"]
