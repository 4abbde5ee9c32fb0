"""The first-run helper process of the demo (liquidamp._warm): markers, no helper when cached."""

from __future__ import annotations

from liquidamp import _warm


def test_helper_marks_each_family_done_even_when_it_fails(tmp_path):
    """An unknown family fails inside the helper: still marked, so the command never hangs."""
    assert _warm.main([str(tmp_path), "no_such_family"]) == 0
    assert (tmp_path / "no_such_family.done").read_text() == "done"


def test_no_helper_without_families_or_with_a_busy_machine(monkeypatch):
    w = _warm.Warmer([])
    assert w.process is None and w.todo == []
    monkeypatch.setattr(_warm, "spare_core", lambda: False)
    w = _warm.Warmer(["effects", "lag"])
    assert w.process is None and w.todo == []
    w.wait("lag")  # returns at once: nothing to wait for
    w.stop()


def test_helper_runs_and_is_waited_for(monkeypatch):
    """A started helper (a family that fails at once) is waited for and ended."""
    monkeypatch.setattr(_warm, "spare_core", lambda: True)
    monkeypatch.setattr(_warm, "_cached", lambda family: False)
    monkeypatch.setitem(_warm.FAMILIES, "nothing", ("nothing", ("coupled/_kernels.py", "x")))
    w = _warm.Warmer(["nothing"])
    assert w.process is not None and w.todo == ["nothing"]
    said = []
    w.wait("nothing", said.append, timeout=60.0)
    assert w.process.wait(timeout=60) == 0
    w.stop()
    assert w.marks is None


def test_one_compile_notice_per_family_and_none_when_silent():
    """A compile of a kernel family's function says so once; the library default is silent."""
    import numba

    import liquidamp.coupled._linalg  # noqa: F401  (a compiled module: numba is set up)
    from liquidamp import _numba_cache as nc

    words = "the rotor and blade integrator (DOP853)"
    nc._state["said"].discard(words)

    def f(x):
        return x + 1

    f.__module__ = "liquidamp.coupled._rotor_kernel"
    g = numba.njit(f)
    g(1)  # silent: no sink
    said = []
    nc.compile_notices(said.append)
    try:
        g(1.5)
        g(1j)  # a second compile of the same family: no second line
    finally:
        nc.compile_notices(None)
    g(True)
    assert said == [f"compiling {words} (once; cached for the next run) ..."]
