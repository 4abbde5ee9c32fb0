"""Atomic outputs: a file or a folder is replaced as a whole or not at all.

Every output of the toolkit (JSON, CSV, device files, figures, HTML reports)
is written to a temporary file in the same folder and renamed over the
target with :func:`os.replace`, which is atomic on POSIX and Windows for
names on one file system.  A full disk, an error half-way or a killed
process therefore leaves either the previous file or the new, whole one,
never a truncated file; the temporary file is removed on an error, and the
error names the target file.

A folder output (a report) is built in a temporary folder beside the target
and swapped in when complete (:func:`atomic_folder`); files of the old
folder that the new one does not write are kept (hard-linked into the new
folder before the swap), so nothing the user put there is lost.

This module imports nothing beyond the standard library.

Examples
--------
>>> import os, tempfile
>>> d = tempfile.mkdtemp()
>>> p = write_text(os.path.join(d, "a.json"), "{}\\n")
>>> open(p).read(), sorted(os.listdir(d))
('{}\\n', ['a.json'])
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "write_text", "write_bytes", "save_figure", "atomic_folder",
           "temporary_name"]


def temporary_name(path: str | Path, tag: str = "tmp") -> Path:
    """A hidden name beside ``path`` that keeps its suffix (matplotlib reads the format off it).

    Examples
    --------
    >>> temporary_name("out/loops.png").name.startswith(".loops.png.")
    True
    >>> temporary_name("out/loops.png").suffix
    '.png'
    """
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.{tag}{path.suffix}")


def _named(exc: OSError, path: Path) -> OSError:
    """``exc`` with the target path as its file name (not the temporary one)."""
    if exc.errno is not None and exc.strerror:
        new = type(exc)(exc.errno, exc.strerror, str(path))
        return new
    return OSError(errno.EIO, str(exc) or type(exc).__name__, str(path))


@contextlib.contextmanager
def atomic_path(path: str | Path, *, fsync: bool = True) -> Iterator[Path]:
    """Context manager: yield a temporary path to write; rename it to ``path`` on success.

    Parameters
    ----------
    path : str or Path
        Final file.  Its folder must exist.
    fsync : bool
        Flush the temporary file to the disk before the rename (default
        True), so that a crash of the machine cannot leave an empty file.

    Yields
    ------
    Path
        Temporary file in the same folder, with the same suffix.

    Raises
    ------
    OSError
        Any error of the writer or of the rename, naming ``path``; the
        temporary file is removed and ``path`` is untouched.

    Examples
    --------
    >>> import os, tempfile
    >>> f = os.path.join(tempfile.mkdtemp(), "x.csv")
    >>> with atomic_path(f) as tmp:
    ...     _ = tmp.write_text("a,b\\n")
    >>> open(f).read()
    'a,b\\n'
    """
    path = Path(path)
    tmp = temporary_name(path)
    try:
        yield tmp
        if fsync:
            fd = os.open(tmp, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise _named(exc, path) from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_path`); return the path."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)
    return path


def write_text(path: str | Path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_path`); return the path.

    Examples
    --------
    >>> import os, tempfile
    >>> f = os.path.join(tempfile.mkdtemp(), "n.txt")
    >>> _ = write_text(f, "old"); _ = write_text(f, "new")
    >>> open(f).read()
    'new'
    """
    return write_bytes(path, text.encode(encoding))


def save_figure(fig, path: str | Path, **kwargs) -> Path:
    """``fig.savefig(path, **kwargs)`` atomically: the previous figure survives a failure.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or Path
        Output file; its suffix chooses the format (``.png``, ``.svg``, ...).
    **kwargs
        Passed to ``savefig`` (e.g. ``dpi``).

    Returns
    -------
    Path
    """
    path = Path(path)
    fmt = kwargs.pop("format", None) or (path.suffix.lstrip(".").lower() or None)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, **kwargs)
    return path


def _exchange(a: Path, b: Path) -> bool:
    """Swap two names atomically (Linux ``renameat2(RENAME_EXCHANGE)``); False if unavailable."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    AT_FDCWD, RENAME_EXCHANGE = -100, 2
    rc = fn(AT_FDCWD, os.fsencode(str(a)), AT_FDCWD, os.fsencode(str(b)), RENAME_EXCHANGE)
    if rc != 0:
        err = ctypes.get_errno()
        if err in (errno.ENOSYS, errno.EINVAL, errno.EOPNOTSUPP):
            return False
        raise OSError(err, os.strerror(err), str(b))
    return True


def _link_tree(src: Path, dst: Path) -> None:
    """Hard-link (else copy) ``src`` into ``dst``: a file or a whole folder."""
    if src.is_dir() and not src.is_symlink():
        shutil.copytree(src, dst, symlinks=True, copy_function=_link_or_copy)
    elif src.is_symlink():
        os.symlink(os.readlink(src), dst)
    else:
        _link_or_copy(src, dst)


def _link_or_copy(src, dst) -> None:
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _inside_cwd(path: Path) -> bool:
    try:
        cwd = Path.cwd().resolve()
    except OSError:
        return False
    target = path.resolve()
    return target == cwd or target in cwd.parents


@contextlib.contextmanager
def atomic_folder(path: str | Path) -> Iterator[Path]:
    """Context manager: yield a temporary folder to fill; swap it in for ``path`` as a whole.

    The temporary folder is created beside ``path`` (same file system).  On
    success, entries of an existing ``path`` that the new folder does not
    hold are hard-linked into it (the user's own files are kept), then the
    two are swapped (atomically where the system can, else by two renames)
    and the old one is removed.  On an error the temporary folder is removed
    and ``path`` is untouched.  Where the folder cannot be swapped (it is
    the working folder or holds it, or its parent is not writable) the
    new files are moved in one by one, each atomically.

    Parameters
    ----------
    path : str or Path
        Output folder (may exist).

    Yields
    ------
    Path
        The temporary folder.

    Examples
    --------
    >>> import os, tempfile
    >>> d = os.path.join(tempfile.mkdtemp(), "report")
    >>> os.mkdir(d); _ = open(os.path.join(d, "notes.txt"), "w").write("mine")
    >>> with atomic_folder(d) as tmp:
    ...     _ = (tmp / "index.html").write_text("<html></html>")
    >>> sorted(os.listdir(d))
    ['index.html', 'notes.txt']
    """
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    inside = path.is_dir() and not os.access(parent, os.W_OK | os.X_OK)
    # a folder in a read-only parent is built inside itself and its files moved in
    stage = (path if inside else parent) / f".{path.name}.{os.getpid()}.building"
    if stage.exists():
        shutil.rmtree(stage)
    try:
        stage.mkdir()
    except OSError as exc:
        raise _named(exc, path) from None
    try:
        yield stage
        if inside:
            _move_in(stage, path)
            shutil.rmtree(stage, ignore_errors=True)
        else:
            _commit(stage, path, parent)
    except BaseException as exc:
        shutil.rmtree(stage, ignore_errors=True)
        if isinstance(exc, OSError) and exc.filename and str(stage) in str(exc.filename):
            raise _named(exc, path / Path(str(exc.filename)).relative_to(stage)) from None
        raise


def _commit(stage: Path, path: Path, parent: Path) -> None:
    if not path.exists():
        os.replace(stage, path)
        return
    if _inside_cwd(path) or not os.access(parent, os.W_OK | os.X_OK):
        _move_in(stage, path)
        shutil.rmtree(stage, ignore_errors=True)
        return
    for entry in path.iterdir():  # keep what the new folder does not replace
        if not (stage / entry.name).exists() and not os.path.lexists(stage / entry.name):
            _link_tree(entry, stage / entry.name)
    old = parent / f".{path.name}.{os.getpid()}.old"
    if _exchange(stage, path):
        shutil.rmtree(stage, ignore_errors=True)  # stage now holds the old folder
        return
    os.replace(path, old)
    try:
        os.replace(stage, path)
    except OSError:
        os.replace(old, path)
        raise
    shutil.rmtree(old, ignore_errors=True)


def _move_in(stage: Path, path: Path) -> None:
    """Move every file of ``stage`` into ``path`` one by one (each rename is atomic)."""
    for src in sorted(stage.rglob("*")):
        rel = src.relative_to(stage)
        dst = path / rel
        if src.is_dir() and not src.is_symlink():
            dst.mkdir(exist_ok=True)
        else:
            os.replace(src, dst)
