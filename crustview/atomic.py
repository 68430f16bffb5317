"""Atomic file writing: a failed, cancelled or killed write leaves the previous file as it was.

Every file crustview writes goes through :func:`atomic_open` (a file object)
or :func:`atomic_path` (a path, for libraries that open files by name):
the content is written to a temporary file in the target's folder, flushed
and synced, and then renamed over the target, so readers see either the
old file or the complete new one.

On Linux the temporary file is *unnamed* (``O_TMPFILE``): until it is given
a name just before the rename, nothing of it is visible in the folder, and
a process killed while writing leaves nothing behind.  Elsewhere (or on a
file system without ``O_TMPFILE``) it is a hidden file
``.NAME.PID.RANDOM.crustview-tmp`` that is removed on failure; one left by
a killed process is removed by the next write to the same target.

Setting the environment variable :data:`PAUSE_ENV` to a number of seconds
makes every write print one line to stderr and sleep between syncing the
data and renaming it over the target (the fault tests kill the process
there).
"""

from __future__ import annotations

import ctypes
import errno
import os
import secrets
import stat
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

#: Test hook: seconds to sleep between writing and renaming (see the module docstring).
PAUSE_ENV = "CRUSTVIEW_TEST_PAUSE_BEFORE_RENAME"
#: The suffix of named temporary files.
TEMP_SUFFIX = ".crustview-tmp"
#: errno values that mean "this folder cannot be written", not "O_TMPFILE is not supported".
_REAL_ERRORS = {errno.ENOENT, errno.ENOTDIR, errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOSPC, errno.EDQUOT}
_AT_FDCWD = -100
_AT_EMPTY_PATH = 0x1000


def _temp_name(target: Path) -> Path:
    return target.with_name(f".{target.name}.{os.getpid()}.{secrets.token_hex(4)}{TEMP_SUFFIX}")


def remove_stale_temporaries(target: str | os.PathLike) -> list[Path]:
    """Remove the named temporary files of ``target`` left by processes that no longer run."""
    target = Path(target)
    removed = []
    try:
        candidates = list(target.parent.glob(f".{target.name}.*{TEMP_SUFFIX}"))
    except OSError:
        return removed
    for tmp in candidates:
        pid_text = tmp.name[len(target.name) + 2 :].split(".", 1)[0]
        if not pid_text.isdigit() or _alive(int(pid_text)):
            continue
        try:
            tmp.unlink()
            removed.append(tmp)
        except OSError:
            pass
    return removed


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _link_unnamed(fd: int, name: Path) -> bool:
    """Give the unnamed file ``fd`` the name ``name`` (linkat); False when the system refuses."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.linkat(fd, b"", _AT_FDCWD, os.fsencode(name), _AT_EMPTY_PATH) == 0:
            return True
    except (OSError, AttributeError):
        pass
    try:  # without CAP_DAC_READ_SEARCH: the documented /proc route
        os.link(f"/proc/self/fd/{fd}", name, follow_symlinks=True)
        return True
    except OSError:
        return False


class AtomicFile:
    """The temporary file of one atomic write, for writers that live longer than one block.

    Write to :attr:`path` (or the descriptor ``fd``), then call :meth:`commit`
    to rename it over ``target``; :meth:`discard` (safe after ``commit``)
    drops it.  :func:`atomic_path` and :func:`atomic_open` wrap this.
    """

    def __init__(self, target: Path) -> None:
        self.target = target
        self.named: Path | None = None
        remove_stale_temporaries(target)
        folder = str(target.parent) or "."
        mode = stat.S_IMODE(os.stat(target).st_mode) if target.is_file() else None
        try:
            self.fd = os.open(folder, os.O_TMPFILE | os.O_RDWR | os.O_CLOEXEC, 0o666)
        except AttributeError:
            self.fd = self._open_named()
        except OSError as err:
            if err.errno in _REAL_ERRORS:
                raise OSError(err.errno, err.strerror, str(target)) from None
            self.fd = self._open_named()
        if mode is not None:
            os.fchmod(self.fd, mode)

    def _open_named(self) -> int:
        self.named = _temp_name(self.target)
        try:
            return os.open(self.named, os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
        except OSError as err:
            raise OSError(err.errno, err.strerror, str(self.target)) from None

    @property
    def path(self) -> str:
        """A name under which other code (or a child process) can open the temporary file."""
        if self.named is not None:
            return str(self.named)
        return f"/proc/{os.getpid()}/fd/{self.fd}"

    def commit(self) -> None:
        os.fsync(self.fd)
        pause = os.environ.get(PAUSE_ENV)
        if pause:
            print(f"crustview: test hook: written, pausing before renaming to '{self.target}'", file=sys.stderr)
            sys.stderr.flush()
            time.sleep(float(pause))
        if self.named is None:
            name = _temp_name(self.target)
            if not _link_unnamed(self.fd, name):
                self._copy_to(name)
            self.named = name
        os.replace(self.named, self.target)
        self.named = None
        os.close(self.fd)
        self.fd = -1
        _sync_folder(self.target.parent)

    def _copy_to(self, name: Path) -> None:
        """Copy the unnamed file into a named one (when it cannot be linked)."""
        out = os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o666)
        self.named = name
        try:
            os.fchmod(out, stat.S_IMODE(os.fstat(self.fd).st_mode))
            offset, size = 0, os.fstat(self.fd).st_size
            while offset < size:
                chunk = os.pread(self.fd, min(1 << 24, size - offset), offset)
                if not chunk:
                    break
                os.write(out, chunk)
                offset += len(chunk)
            os.fsync(out)
        finally:
            os.close(out)

    def discard(self) -> None:
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1
        if self.named is not None:
            try:
                self.named.unlink()
            except OSError:
                pass
            self.named = None


def _sync_folder(folder: Path) -> None:
    try:
        fd = os.open(str(folder) or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


@contextmanager
def atomic_path(target: str | os.PathLike) -> Iterator[str]:
    """A path to write ``target``'s new content to; renamed over ``target`` when the block ends without error.

    The path may have no suffix (``/proc/PID/fd/N``): tell libraries the
    format explicitly.  Any exception (including KeyboardInterrupt) discards
    the new content and leaves ``target`` unchanged.

    Raises
    ------
    OSError
        With ``filename`` set to ``target`` when the folder cannot be written.
    """
    staged = AtomicFile(Path(target))
    try:
        yield staged.path
        staged.commit()
    finally:
        staged.discard()


@contextmanager
def atomic_open(target: str | os.PathLike, mode: str = "wb", encoding: str | None = None) -> Iterator[IO]:
    """A file object for ``target``'s new content; see :func:`atomic_path`.

    Parameters
    ----------
    target : path-like
    mode : {"wb", "w"}
    encoding : str, optional
        For text mode (default UTF-8).
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open writes new files only (mode 'w' or 'wb'), not {mode!r}")
    staged = AtomicFile(Path(target))
    try:
        fh = os.fdopen(os.dup(staged.fd), mode, encoding=None if mode == "wb" else (encoding or "utf-8"))
        with fh:
            yield fh
        staged.commit()
    finally:
        staged.discard()


def write_bytes(target: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``target`` atomically."""
    with atomic_open(target, "wb") as fh:
        fh.write(data)


def write_text(target: str | os.PathLike, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``target`` atomically."""
    with atomic_open(target, "w", encoding=encoding) as fh:
        fh.write(text)
