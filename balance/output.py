"""Writing results safely: whole files or nothing.

Output goes to a temporary file beside the target and is renamed into place, so an
interrupted or failed run leaves any previous file intact.  An existing file is only
replaced when asked to (``force``).
"""

from __future__ import annotations

import os
import signal
import tempfile
from collections.abc import Callable
from pathlib import Path

from .errors import InputError

__all__ = ["check_target", "write_atomic"]


def check_target(path: str | Path, force: bool = False) -> Path:
    """Check that ``path`` can be written; return it as a Path.

    Raises
    ------
    InputError
        If the directory does not exist or is not writable, if the path is a directory,
        or if the file exists and ``force`` is false.
    """
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if target.is_dir():
        raise InputError(f"{target}: is a directory; give a file name")
    if parent.exists() and not parent.is_dir():
        raise InputError(f"{target}: {parent} is not a directory")
    if not parent.is_dir():
        raise InputError(f"{target}: directory {parent} does not exist; create it first")
    if not os.access(parent, os.W_OK):
        raise InputError(f"{target}: directory {parent} is not writable")
    if target.exists() and not force:
        raise InputError(f"{target}: file exists; use --force to replace it")
    return target


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
    # no signal may land between creating the temporary file and knowing its name
    blocked = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
    try:
        try:
            handle, tmp_name = tempfile.mkstemp(
                prefix=f".{target.name}.", suffix=".part", dir=target.parent
            )
            tmp = Path(tmp_name)
            os.close(handle)
            # mkstemp makes the file private; results are ordinary files (0666 & ~umask)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)
        write(tmp)
        os.replace(tmp, target)
    except BaseException:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
        raise
    return target
