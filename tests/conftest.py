"""Shared fixtures: the real measured records of ../shared/ (skipped where absent)."""

from pathlib import Path

import pytest

#: The real test-machine records of a banded rotary friction damper with backlash
#: (CC BY-SA 4.0, Coble, Huggins, Cao, Ricles, Downey 2022; see the folder's README).
FRICTION_DAMPER_DIR = next(
    (d for d in (p / "shared" / "data" / "friction-damper-backlash"
                 for p in Path(__file__).resolve().parents[1:4])
     if (d / "brfd30_0.5Hz_0.5in_steady.csv").is_file()),
    Path(__file__).resolve().parents[1].parent / "shared" / "data" / "friction-damper-backlash")


@pytest.fixture(scope="session")
def friction_damper_records() -> Path:
    """Folder of the friction-damper-with-backlash records; skips the test where it is absent."""
    if not (FRICTION_DAMPER_DIR / "brfd30_0.5Hz_0.5in_steady.csv").is_file():
        pytest.skip(f"real records not found at {FRICTION_DAMPER_DIR} (the ../shared/ folder "
                    "beside the repository is not on this machine); synthetic records cover "
                    "the same code paths")
    return FRICTION_DAMPER_DIR
