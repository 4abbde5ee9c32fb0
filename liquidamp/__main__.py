"""``python -m liquidamp``: the ``liquidamp`` command line (:func:`liquidamp.cli.main`)."""

import sys

from liquidamp.cli import main

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
