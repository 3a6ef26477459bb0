"""Writing results safely: whole files or nothing.

Output goes to a temporary file beside the target and is renamed into place, so an
interrupted or failed run leaves any previous file intact.  An existing file is only
replaced when asked to (``force``).
"""

from __future__ import annotations

import os
import shutil
import signal
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from balance.core.errors import InputError

__all__ = ["check_directory_target", "check_target", "write_atomic", "write_atomic_directory"]


def _check_parent(target: Path) -> None:
    parent = target.parent if str(target.parent) else Path(".")
    if parent.exists() and not parent.is_dir():
        raise InputError(f"{target}: {parent} is not a directory")
    if not parent.is_dir():
        raise InputError(f"{target}: directory {parent} does not exist; create it first")
    if not os.access(parent, os.W_OK):
        raise InputError(f"{target}: directory {parent} is not writable")


def check_target(path: str | Path, force: bool = False) -> Path:
    """Check that ``path`` can be written; return it as a Path.

    Raises
    ------
    InputError
        If the directory does not exist or is not writable, if the path is a directory,
        or if the file exists and ``force`` is false.
    """
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{target}: is a directory; give a file name")
    _check_parent(target)
    if target.exists() and not force:
        raise InputError(f"{target}: file exists; use --force to replace it")
    return target


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


@contextmanager
def _signals_blocked() -> Iterator[None]:
    """No SIGINT or SIGTERM lands between creating a temporary and knowing its name."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def write_atomic(path: str | Path, write: Callable[[Path], None], force: bool = False) -> Path:
    """Write a file through ``write(temporary_path)`` and rename it into place.

    Parameters
    ----------
    path : str or Path
        The target file.
    write : callable
        Writes the complete file at the temporary path it is given.
    force : bool
        Replace an existing file.

    Returns
    -------
    Path
        The target path.
    """
    target = check_target(path, force)
    tmp: Path | None = None
    try:
        with _signals_blocked():
            handle, tmp_name = tempfile.mkstemp(
                prefix=f".{target.name}.", suffix=".part", dir=target.parent
            )
            tmp = Path(tmp_name)
            os.close(handle)
            # mkstemp makes the file private; results are ordinary files (0666 & ~umask)
            os.chmod(tmp, 0o666 & ~_umask())
        write(tmp)
        os.replace(tmp, target)
    except BaseException:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
        raise
    return target


def check_directory_target(
    path: str | Path,
    force: bool = False,
    is_replaceable: Callable[[Path], bool] = lambda p: False,
) -> Path:
    """Check that a directory output (a Zarr store) can be written; return it as a Path.

    Raises
    ------
    InputError
        If the parent directory is missing or not writable, if the target exists and
        ``force`` is false, or if it is a directory that ``is_replaceable`` refuses.
    """
    target = Path(path)
    _check_parent(target)
    if target.exists():
        if not force:
            raise InputError(f"{target}: exists; use --force to replace it")
        if target.is_dir() and not is_replaceable(target):
            raise InputError(
                f"{target}: is a directory that is not a Zarr store; will not replace it"
            )
    return target


def write_atomic_directory(
    path: str | Path,
    write: Callable[[Path], None],
    force: bool = False,
    is_replaceable: Callable[[Path], bool] = lambda p: False,
) -> Path:
    """Write a directory (a Zarr store) through ``write(temporary_dir)``, then move it in.

    An existing target is replaced only with ``force`` and only if it is a file or a
    directory that ``is_replaceable`` accepts (a Zarr store, not any directory): it is
    moved aside, the new directory moved in, and the old one deleted.  A failed or
    interrupted write leaves the old target as it was.
    """
    target = check_directory_target(path, force, is_replaceable)
    tmp: Path | None = None
    try:
        with _signals_blocked():
            tmp = Path(
                tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
            )
            os.chmod(tmp, 0o777 & ~_umask())
        write(tmp)
        if target.exists():
            old = Path(
                tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent)
            )
            os.replace(target, old / "previous")
            try:
                os.replace(tmp, target)
            except BaseException:
                os.replace(old / "previous", target)
                raise
            finally:
                shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, target)
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    return target
