"""Writing results safely: whole files or nothing.

An existing file is only replaced when asked to (``force``), and the target path only ever
holds the previous file or the complete new one, never a part of either.  What is promised
when a write is interrupted:

* **SIGTERM or SIGINT in the command line**: no temporary file or directory is left
  behind, whatever the moment.  The command line's handler removes the run's temporaries
  and ends the process at once (:func:`exit_now`); it raises nothing into the interrupted
  code, which could then hang on a lock it held (xarray's netCDF writer can).  A Zarr
  store, whose chunks zarr writes from a thread pool, is instead stopped at its next
  :func:`checkpoint` (between chunks, when no thread writes into it); a second signal
  ends it at once.
* **An exception** (including the ``KeyboardInterrupt`` or ``SystemExit`` a library user's
  signal handler raises): likewise nothing is left once the process exits.  The
  temporary's name is chosen and registered *before* it is created, so there is no moment
  at which it exists without the code that removes it knowing its name.  (Blocking the
  signals around the creation is not enough: a signal mask is per thread, and a
  process-directed signal is taken by any thread that does not block it, such as the
  OpenBLAS workers numpy starts, after which Python runs the handler in the main thread at
  once.)  Removal runs from the exception handler and again at interpreter exit, after
  the other threads have finished, in case the first attempt was itself interrupted or a
  writer's thread was still writing.
* **SIGKILL or a crash** (no code runs): the target is still the previous file or the
  complete new one.  Output given as bytes is written to an anonymous ``O_TMPFILE`` file
  (Linux, on file systems that support it) and linked into place only when complete, so
  no partial file ever has a name.  Output written by a library through a path (netCDF,
  Zarr, figures saved by matplotlib) goes to a hidden temporary beside the target, named
  ``.<target>.<owner>.<random>.part``, where ``<owner>`` names the writing process (its
  pid and start time, and a key for this machine's boot and pid namespace).  Such a file
  cannot be mistaken for output, and the next write into the same directory removes every
  temporary whose owner is no longer running.  (Replacing an existing file needs a link to
  a temporary name and a rename, two system calls; a SIGKILL between them leaves a
  *complete* hidden temporary, removed the same way.)

A directory (a Zarr store) replaces an existing one with one atomic exchange
(``renameat2(RENAME_EXCHANGE)``) where the system has it, so the target never goes
missing; elsewhere the old store is moved aside first, and a write killed between the two
renames is rolled back by the next write.

Durability across a power cut (``fsync``) is not attempted.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import hashlib
import os
import re
import secrets
import shutil
import sys
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import NoReturn

from balance.core.errors import InputError, OutputExists

__all__ = [
    "check_directory_target",
    "check_target",
    "checkpoint",
    "exit_now",
    "stop_at_checkpoint",
    "write_atomic",
    "write_atomic_directory",
    "writing",
]

Writer = Callable[[Path], object]


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

    Parameters
    ----------
    path : str or Path
        The target file.
    force : bool
        Replace an existing file.

    Returns
    -------
    Path
        The target.

    Raises
    ------
    OutputExists
        If the file exists and ``force`` is false.
    InputError
        If the directory does not exist or is not writable, or if the path is a directory.
    """
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{target}: is a directory; give a file name")
    _check_parent(target)
    if target.exists() and not force:
        raise OutputExists(target)
    return target


# --------------------------------------------------------------------------- temporaries

#: ``.<target name>.<key>-<pid>-<start>.<random>.<part|old>``
_TEMPORARY = re.compile(
    r"^\.(?P<target>.+)\.(?P<key>[0-9a-f]{8})-(?P<pid>[0-9]+)-(?P<start>[0-9]+)"
    r"\.[0-9a-f]{12}\.(?P<kind>part|old)$"
)


def _read(path: str) -> str | None:
    try:
        with open(path, encoding="ascii", errors="replace") as f:
            return f.read()
    except OSError:
        return None


def _start_time(pid: int) -> int | None:
    """When process ``pid`` started (clock ticks after boot), or None if it is not running.

    A zombie (killed, not yet reaped) is not running: it holds no files and writes nothing.
    """
    stat = _read(f"/proc/{pid}/stat")
    if stat is None:
        return None
    fields = stat[stat.rfind(")") + 2 :].split()  # after "pid (command) "
    if len(fields) < 20 or fields[0] in ("Z", "X", "x"):
        return None
    return int(fields[19])


@cache
def _machine_key() -> str | None:
    """Eight hex digits naming this boot of this machine and this pid namespace, or None
    where processes cannot be looked up (no /proc): temporaries are then never removed by
    others, because nobody can tell whether their owner still runs."""
    boot = _read("/proc/sys/kernel/random/boot_id")
    if boot is None or _start_time(os.getpid()) is None:
        return None
    try:
        namespace = os.stat("/proc/self/ns/pid").st_ino
    except OSError:
        namespace = 0
    return hashlib.sha256(f"{boot.strip()} {namespace}".encode()).hexdigest()[:8]


@cache
def _owner(pid: int) -> str:
    """This process in a temporary's name (cached per pid, so a forked child is new)."""
    key = _machine_key()
    start = _start_time(pid) if key is not None else None
    return f"{key or 'ffffffff'}-{pid}-{start if start is not None else 0}"


def _temporary(target: Path, kind: str) -> Path:
    name = f".{target.name}.{_owner(os.getpid())}.{secrets.token_hex(6)}.{kind}"
    return target.parent / name


def _discard(path: Path) -> None:
    """Remove a temporary file or directory, if it is there."""
    with contextlib.suppress(OSError):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)


def _settle_old(old: Path, target: Path) -> None:
    """Finish with a directory that holds a target moved aside (``old / 'previous'``):
    put it back if the target is missing (the new one never arrived), else delete it."""
    previous = old / "previous"
    if os.path.lexists(previous) and not os.path.lexists(target):
        with contextlib.suppress(OSError):
            os.replace(previous, target)
    _discard(old)


#: Temporaries of this process that exist or are about to: how to remove each, and whether
#: its writer writes from other threads (a Zarr store's chunks are written by a thread pool)
#: (keyed by path; the pid guards against a forked child removing its parent's files).
_PENDING: dict[Path, tuple[int, Callable[[], None], bool]] = {}

#: Exit codes asked for by a signal while a threaded write was under way (see
#: :func:`stop_at_checkpoint`).
_STOP: list[int] = []


def _register(path: Path, cleanup: Callable[[], None], threaded: bool = False) -> None:
    _PENDING[path] = (os.getpid(), cleanup, threaded)


def _unregister(path: Path) -> None:
    _PENDING.pop(path, None)


@atexit.register
def _clean_up_at_exit() -> None:
    for path, (pid, cleanup, _) in list(_PENDING.items()):
        if pid == os.getpid():
            cleanup()
        _PENDING.pop(path, None)


def writing() -> bool:
    """Whether this process has a write under way (or a failed one not yet cleaned up)."""
    pid = os.getpid()
    return any(entry[0] == pid for entry in list(_PENDING.values()))


def exit_now(code: int) -> NoReturn:
    """Remove this process's temporaries and end it at once (``os._exit(code)``).

    For a signal handler (the command line's, for SIGTERM and for SIGINT during a write):
    no code of the interrupted write runs on.  Raising an exception from the handler
    instead unwinds through whatever library code was running, which may then hang on a
    lock it held when the exception arrived (xarray's netCDF writer does), or go on
    writing.

    Parameters
    ----------
    code : int
        The process's exit status.
    """
    _clean_up_at_exit()
    os._exit(code)


def stop_at_checkpoint(code: int) -> bool:
    """For a signal handler: ask a threaded write under way to stop at its next
    :func:`checkpoint`.

    Removing a directory while the writer's threads still write into it (and re-create
    it) could leave a part behind; at a checkpoint none of them is writing.

    Parameters
    ----------
    code : int
        The exit status that :func:`checkpoint` raises ``SystemExit`` with.

    Returns
    -------
    bool
        True if such a write is under way and has been asked to stop; False if there is none,
        or if a signal has asked already (then the handler should :func:`exit_now`).
    """
    pid = os.getpid()
    threaded = any(entry[0] == pid and entry[2] for entry in list(_PENDING.values()))
    if not threaded or _STOP:
        return False
    _STOP.append(code)
    return True


def checkpoint() -> None:
    """Where a threaded writer has no write in flight (between the chunks of a sweep, and
    before a written directory is moved into place): end the run if a signal asked to.

    Raises
    ------
    SystemExit
        With the code the signal asked for (:func:`stop_at_checkpoint`).
    """
    if _STOP:
        raise SystemExit(_STOP[0])


def _remove_orphans(directory: str | Path) -> list[Path]:
    """Remove the temporaries in ``directory`` left by writes whose process was killed.

    Only temporaries of this machine (and pid namespace) whose owner is no longer running
    are touched; a target that a killed directory write had moved aside is put back.
    Every write calls this for its directory first.

    Returns
    -------
    list of Path
        What was removed (or put back).
    """
    key = _machine_key()
    if key is None:
        return []
    removed = []
    try:
        names = os.listdir(directory)
    except OSError:
        return []
    for name in names:
        match = _TEMPORARY.match(name)
        if match is None or match["key"] != key:
            continue
        if _start_time(int(match["pid"])) == int(match["start"]):
            continue  # its writer is still at work
        path = Path(directory, name)
        if match["kind"] == "old":
            _settle_old(path, path.parent / match["target"])
        else:
            _discard(path)
        removed.append(path)
    return removed


# --------------------------------------------------------------------------- files


class _NotLinked(Exception):
    """Linking a file in through /proc is not possible here."""


def _through_temporary(target: Path, fill: Callable[[Path], None]) -> None:
    """``fill(temporary)`` a file next to ``target``, then move it onto ``target``.

    The temporary is registered before it exists and removed on any failure or interrupt,
    so that no partial or temporary file is left behind, whatever the timing.  After a
    failure it stays registered and is removed again at exit, in case a thread of the
    writer was still writing to it.
    """
    tmp = _temporary(target, "part")
    _register(tmp, lambda: _discard(tmp))  # before the file exists: no unknown temporary
    try:
        fill(tmp)
        os.replace(tmp, target)
    except BaseException:
        _discard(tmp)
        raise
    _unregister(tmp)


def _link_anonymous(target: Path, data: bytes | bytearray | memoryview, force: bool) -> bool:
    """Write ``data`` to an anonymous file and link it in as ``target``.

    Returns False (nothing done) where O_TMPFILE or linking through /proc is unavailable.
    """
    flag = getattr(os, "O_TMPFILE", 0)
    if not flag:
        return False
    try:
        fds = os.open("/proc/self/fd", os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return False
    try:
        fd = os.open(target.parent, flag | os.O_WRONLY | os.O_CLOEXEC, 0o666)
    except OSError:
        os.close(fds)
        return False
    try:
        view = memoryview(data).cast("B")
        while view:
            view = view[os.write(fd, view) :]

        def link(name: Path) -> None:
            # linkat(AT_SYMLINK_FOLLOW) on /proc/self/fd/N: the file gets its first name
            os.link(str(fd), name, src_dir_fd=fds, follow_symlinks=True)

        def link_temporary(tmp: Path) -> None:
            try:
                link(tmp)
            except OSError as exc:
                raise _NotLinked from exc

        if not os.path.lexists(target):
            try:
                link(target)  # appears whole, at once
                return True
            except FileExistsError:
                if not force:
                    raise OutputExists(target) from None
            except OSError:
                return False
        try:
            _through_temporary(target, link_temporary)
        except _NotLinked:
            return False
        return True
    finally:
        os.close(fd)
        os.close(fds)


def write_atomic(
    path: str | Path, write: Writer | bytes | bytearray | memoryview, force: bool = False
) -> Path:
    """Write a whole file, or nothing: through ``write(temporary_path)``, or given its bytes.

    The file gets the usual permissions (0666 less the umask).

    Parameters
    ----------
    path : str or Path
        The target file.
    write : callable or bytes
        Either the file's contents, or a function that writes the complete file at the
        temporary path it is given (and closes it) before returning.
    force : bool
        Replace an existing file.

    Returns
    -------
    Path
        The target path.
    """
    target = check_target(path, force)
    _remove_orphans(target.parent)
    writer: Writer
    if isinstance(write, (bytes, bytearray, memoryview)):
        data = write
        if _link_anonymous(target, data, force):
            return target

        def writer(tmp: Path) -> None:
            tmp.write_bytes(data)

    else:
        writer = write

    def fill(tmp: Path) -> None:
        os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o666))
        writer(tmp)

    _through_temporary(target, fill)
    return target


# --------------------------------------------------------------------------- directories


def check_directory_target(
    path: str | Path,
    force: bool = False,
    is_replaceable: Callable[[Path], bool] = lambda p: False,
) -> Path:
    """Check that a directory output (a Zarr store) can be written; return it as a Path.

    Parameters
    ----------
    path : str or Path
        The target directory.
    force : bool
        Replace an existing target.
    is_replaceable : callable
        ``is_replaceable(path)``: whether an existing directory may be replaced (a Zarr
        store, not any directory).

    Returns
    -------
    Path
        The target.

    Raises
    ------
    OutputExists
        If the target exists and ``force`` is false.
    InputError
        If the parent directory is missing or not writable, or if the target is a directory
        that ``is_replaceable`` refuses.
    """
    target = Path(path)
    _check_parent(target)
    if target.exists():
        if not force:
            raise OutputExists(target, "exists")
        if target.is_dir() and not is_replaceable(target):
            raise InputError(
                f"{target}: is a directory that is not a Zarr store; will not replace it"
            )
    return target


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (``renameat2(RENAME_EXCHANGE)``); False if unsupported."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p]
    renameat2.argtypes += [ctypes.c_uint]
    at_fdcwd, rename_exchange = -100, 2
    if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.ENOTSUP):
        return False
    raise OSError(code, os.strerror(code), str(a), None, str(b))


def write_atomic_directory(
    path: str | Path,
    write: Writer,
    force: bool = False,
    is_replaceable: Callable[[Path], bool] = lambda p: False,
) -> Path:
    """Write a directory (a Zarr store) through ``write(temporary_dir)``, then move it in.

    An existing target is replaced only with ``force`` and only if it is a file or a
    directory that ``is_replaceable`` accepts (a Zarr store, not any directory): the two
    are exchanged in one step and the old one deleted.  A failed or interrupted write
    leaves the old target as it was.

    Parameters
    ----------
    path : str or Path
        The target directory.
    write : callable
        ``write(temporary_dir)`` writes the complete directory's contents.
    force : bool
        Replace an existing target.
    is_replaceable : callable
        ``is_replaceable(path)``: whether an existing directory may be replaced.

    Returns
    -------
    Path
        The target.
    """
    target = check_directory_target(path, force, is_replaceable)
    _remove_orphans(target.parent)
    tmp = _temporary(target, "part")
    _register(tmp, lambda: _discard(tmp), threaded=True)
    try:
        os.mkdir(tmp, 0o777)
        write(tmp)
        checkpoint()  # a signal during the write: stop here, with the old target in place
        # after an exchange tmp holds the previous target, removed below
        if not (os.path.lexists(target) and _exchange(tmp, target)):
            if os.path.lexists(target):
                _replace_by_moving_aside(tmp, target)
            else:
                os.replace(tmp, target)
    except BaseException:
        _discard(tmp)
        # no longer written, but still registered: removed again at exit, after the threads
        # of the writer (Zarr writes chunks from a thread pool) have finished with it
        _register(tmp, lambda: _discard(tmp))
        raise
    _discard(tmp)
    _unregister(tmp)
    return target


def _replace_by_moving_aside(tmp: Path, target: Path) -> None:
    old = _temporary(target, "old")
    _register(old, lambda: _settle_old(old, target))
    try:
        os.mkdir(old, 0o700)
        os.replace(target, old / "previous")
        os.replace(tmp, target)
    finally:
        _settle_old(old, target)
        _unregister(old)
