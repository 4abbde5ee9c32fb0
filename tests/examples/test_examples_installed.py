"""The example scripts ship inside the package and run with ``python -m``."""

import subprocess
import sys

import pytest


@pytest.mark.parametrize("name", ["ground_resonance_map", "flutter_map"])
def test_example_runs_from_the_installed_package(name):
    out = subprocess.run([sys.executable, "-m", f"liquidamp.examples.{name}", "--help"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "--out" in out.stdout and "--dask" in out.stdout
