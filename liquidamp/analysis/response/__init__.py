"""Linear and equivalent models of the device and its periodic response.

* :mod:`.linear` -- transfer functions K(s) = F(s)/Y(s) (Titurus 2018, eqs. 16, 18, 19) and
  state-space linearization at rest.
* :mod:`.iosys` -- device models as python-control nonlinear I/O systems.
* :mod:`.harmonics` -- first harmonic and dynamic stiffness K* = F1/Y of a periodic response.
* :mod:`.equivalent` -- equivalent (describing-function) linearization at finite amplitude.
* :mod:`.stiffness` -- dynamic-stiffness sweeps K*(f; Y): nonlinear, linear and equivalent.
* :mod:`.periodic` -- the periodic steady state by shooting.
"""
