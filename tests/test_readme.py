"""The README's Python quick start: at most three imports, and it runs as printed."""

from __future__ import annotations

import ast
import contextlib
import io
import re
import warnings
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def _quick_start() -> str:
    text = README.read_text()
    m = re.search(r"## Python quick start\n\n```python\n(.*?)```", text, re.S)
    assert m, "README has no Python quick start block"
    return m.group(1)


def test_quick_start_needs_at_most_three_imports():
    tree = ast.parse(_quick_start())
    imports = [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))]
    assert 1 <= len(imports) <= 3
    assert all(getattr(n, "module", "liquidamp") == "liquidamp" for n in imports)


def test_quick_start_runs_and_prints_its_numbers():
    out = io.StringIO()
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # the current names only
        with contextlib.redirect_stdout(out):
            exec(compile(_quick_start(), str(README), "exec"), {})
    first, second = out.getvalue().splitlines()
    mag, phase = re.match(r"\|K\*\| = (\S+) N/m, phase (\S+) deg", first).groups()
    assert abs(float(mag) - 1.306e5) < 0.002e5 and abs(float(phase) - 66.4) < 0.2
    # the linear model is a complex scalar within 3 % of |K*| (the README's claim)
    re_, im, rel = re.match(r"K\(i w\) = (\S+?e[+-]\d+)\+(\S+)j N/m, (\S+)% from",
                            second).groups()
    assert abs(float(rel)) < 3.0 and float(re_) > 0 and float(im) > 0
