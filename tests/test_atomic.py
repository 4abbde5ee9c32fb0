"""Nothing lost: outputs replaced whole or not at all (disk full, errors, a killed process).

A full disk is a real small tmpfs where the test may mount one (root on Linux), else
a disk-full error raised when the file is flushed (``os.fsync``), which is where
delayed-allocation file systems report it.
"""

import errno
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from liquidamp import atomic
from liquidamp.cli import main


@pytest.fixture(params=["tmpfs", "fsync"])
def full_folder(tmp_path, monkeypatch, request):
    """A folder whose disk is full, holding ``old.json``, ``old.png`` and ``d.toml``."""
    small = tmp_path / "small"
    small.mkdir()
    mounted = False
    if request.param == "tmpfs":
        if not (hasattr(os, "geteuid") and os.geteuid() == 0):
            pytest.skip("mounting a small tmpfs needs root")
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs",
                                  str(small)], capture_output=True).returncode == 0
        if not mounted:
            pytest.skip("cannot mount a tmpfs here")
    (small / "old.json").write_text('{"old": true}\n')
    (small / "old.png").write_bytes(b"\x89PNG old figure")
    (small / "d.toml").write_text("# old\n")
    if mounted:
        fd = os.open(small / "filler", os.O_WRONLY | os.O_CREAT)
        try:  # fill the disk to the last block
            while True:
                os.write(fd, b"\0" * 4096)
        except OSError as exc:
            assert exc.errno == errno.ENOSPC
        finally:
            os.close(fd)
    else:
        def full(fd):
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(atomic.os, "fsync", full)
    try:
        yield small
    finally:
        if mounted:
            subprocess.run(["umount", str(small)], check=False)


def _no_temporary_files(folder: Path) -> bool:
    return not [p for p in folder.iterdir() if p.name.startswith(".")]


def test_disk_full_keeps_the_previous_json_and_names_the_file(full_folder, capsys):
    target = full_folder / "old.json"
    code = main(["params", "--preset", "reference", "--json", str(target)])
    err = capsys.readouterr().err
    assert code == 2
    assert f"liquidamp params: error: {target}: No space left on device" in err
    assert target.read_text() == '{"old": true}\n'
    assert _no_temporary_files(full_folder)


def test_disk_full_keeps_the_previous_figure_and_device_file(full_folder):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    with pytest.raises(OSError) as exc:
        atomic.save_figure(fig, full_folder / "old.png", dpi=300)
    plt.close(fig)
    assert exc.value.errno == errno.ENOSPC and exc.value.filename == str(full_folder / "old.png")
    assert (full_folder / "old.png").read_bytes() == b"\x89PNG old figure"
    from liquidamp.device import preset, write_device_file

    with pytest.raises(OSError, match="No space left"):
        write_device_file(full_folder / "d.toml", preset("reference"))
    assert (full_folder / "d.toml").read_text() == "# old\n"
    assert _no_temporary_files(full_folder)


def test_report_folder_is_replaced_whole_and_keeps_the_users_files(tmp_path):
    out = tmp_path / "report"
    out.mkdir()
    (out / "index.html").write_text("old report")
    (out / "notes.txt").write_text("mine")
    with pytest.raises(RuntimeError), atomic.atomic_folder(out) as stage:
        (stage / "index.html").write_text("half a new report")
        raise RuntimeError("the plot failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]
    assert (out / "index.html").read_text() == "old report"
    with atomic.atomic_folder(out) as stage:
        (stage / "index.html").write_text("new report")
        (stage / "a.png").write_bytes(b"png")
    assert (out / "index.html").read_text() == "new report"
    assert (out / "notes.txt").read_text() == "mine" and (out / "a.png").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]


_WRITER = r"""
import sys
from liquidamp.atomic import write_text
path, n = sys.argv[1], 0
print("ready", flush=True)
while True:
    n += 1
    write_text(path, '{"n": %d, "payload": "%s"}\n' % (n, "x" * 4_000_000))
"""


def test_a_killed_writer_leaves_the_old_file_or_the_new_whole_one(tmp_path):
    """SIGKILL at several moments of a loop of 4 MB writes: the file always parses."""
    path = tmp_path / "out.json"
    path.write_text('{"n": 0, "payload": ""}\n')
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[1]),
                                         env.get("PYTHONPATH", "")])
    seen = set()
    for delay in (0.05, 0.13, 0.31, 0.47):
        p = subprocess.Popen([sys.executable, "-c", _WRITER, str(path)], env=env,
                             stdout=subprocess.PIPE, text=True)
        assert p.stdout.readline().strip() == "ready"
        time.sleep(delay)
        p.send_signal(signal.SIGKILL)
        p.wait()
        p.stdout.close()
        data = json.loads(path.read_text())  # never truncated
        assert data["n"] == 0 or len(data["payload"]) == 4_000_000
        seen.add(data["n"])
    assert len(seen) >= 2, seen  # the kills did land while it was writing
