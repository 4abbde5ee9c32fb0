"""Shared fixtures: the real measured records of ../shared/ (skipped where absent)."""

import os
from pathlib import Path

import pytest


def _shared_data() -> Path:
    """The ../shared/data folder beside the repository (or beside a parent folder of it, as
    for a git worktree), else where it would be beside the repository."""
    here = Path(__file__).resolve()
    for parent in here.parents[1:]:
        if (parent / "shared" / "data").is_dir():
            return parent / "shared" / "data"
    return here.parents[1].parent / "shared" / "data"


SHARED_DATA = _shared_data()
#: The real test-machine records of a banded rotary friction damper with backlash
#: (CC BY-SA 4.0, Coble, Huggins, Cao, Ricles, Downey 2022; see the folder's README).
FRICTION_DAMPER_DIR = SHARED_DATA / "friction-damper-backlash"
#: Synthetic records with undeclared effects made by an independent simulator (CC0; README
#: and truth.json in the folder).
INDEPENDENT_DIR = SHARED_DATA / "independent-records"


@pytest.fixture(scope="session")
def friction_damper_records() -> Path:
    """Folder of the friction-damper-with-backlash records; skips the test where it is absent."""
    if not (FRICTION_DAMPER_DIR / "brfd30_0.5Hz_0.5in_steady.csv").is_file():
        pytest.skip(f"real records not found at {FRICTION_DAMPER_DIR} (the ../shared/ folder "
                    "beside the repository is not on this machine); synthetic records cover "
                    "the same code paths")
    return FRICTION_DAMPER_DIR


@pytest.fixture(scope="session")
def independent_records() -> Path:
    """Folder of the independent synthetic records; skips the test where it is absent."""
    if not (INDEPENDENT_DIR / "truth.json").is_file():
        pytest.skip(f"independent records not found at {INDEPENDENT_DIR} (the ../shared/ "
                    "folder beside the repository is not on this machine)")
    return INDEPENDENT_DIR


def pytest_configure(config):
    """Under pytest-xdist (the suite's default, ``-n auto``) each worker's fits take their
    share of the cores for their Jacobian columns (``LIQUIDAMP_THREADS``), so that two
    workers on two cores do not each start two threads; a value already set is kept.  The
    answers do not depend on the thread count (``fit_objective``)."""
    workers = os.environ.get("PYTEST_XDIST_WORKER_COUNT")
    if workers and not os.environ.get("LIQUIDAMP_THREADS"):
        from liquidamp.analysis.measured.fit_objective import fit_threads  # the usable cores

        os.environ["LIQUIDAMP_THREADS"] = str(max(1, fit_threads() // max(1, int(workers))))
