"""Sub-commands of the ``liquidamp`` command line, one module each.

A module here defines ``register(subparsers)``, which adds its parser and
sets ``func`` to a callable taking the parsed arguments and returning an exit
code.  Shared argument parsing (lists, lengths with units) is in
:mod:`liquidamp.commands._args`.
"""

from liquidamp.commands._stderr import route_warnings

__all__ = ["route_warnings"]
