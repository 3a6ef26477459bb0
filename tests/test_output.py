"""Output safety: whole files or nothing, even when a run is killed while it writes."""

from __future__ import annotations

import gc
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from helpers import needs

from balance.core.errors import InputError
from balance.io import atomic
from balance.io.atomic import check_target, write_atomic, write_atomic_directory

OLD = b"the previous result, which must survive\n"
NEW = b"the complete new result\n"
ORDERS = 1000
OPTIONS = ["--orders", f"1-{ORDERS}"]


def _big_layout(path: Path, n: int = 256) -> Path:
    rng = np.random.default_rng(7)
    rows = "\n".join(
        f"  - {{throw: {t:.3f} deg, bank: {b:.3f} deg, z: {90 * i} mm}}"
        for i, (t, b) in enumerate(
            zip(rng.uniform(0, 360, n), rng.uniform(-60, 60, n), strict=True)
        )
    )
    path.write_text(
        "name: big\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\ncylinders:\n" + rows + "\n"
    )
    return path


def _sigint_default() -> None:
    """In the child before it starts: SIGINT at its default disposition.  A shell starts a
    background job (``pytest &``) with SIGINT ignored, the ignored disposition survives
    ``exec``, and Python, and balance after it, rightly leave it ignored: the run would then
    finish its write whatever SIGINT the test sends (see
    :func:`test_a_run_started_with_sigint_ignored_finishes_its_write`)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _run_and_signal(
    layout: Path, target: Path, sig: int, *, sigint: Callable[[], None] | None = _sigint_default
) -> subprocess.Popen[bytes]:
    """Start a netCDF write and send ``sig`` as soon as its temporary file appears."""
    command = [sys.executable, "-m", "balance", "analyse", str(layout), "-f", "netcdf"]
    proc = subprocess.Popen(
        [*command, *OPTIONS, "-o", str(target), "--force"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        preexec_fn=sigint,
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if list(target.parent.glob(f".{target.name}.*.part")):
            proc.send_signal(sig)
            break
        time.sleep(0.0002)
    proc.wait(timeout=120)
    return proc


def _is_complete_result(path: Path) -> bool:
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        return len(nc.dimensions["order"]) == ORDERS and "reciprocating_force_peak" in nc.variables


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT])
def test_killed_netcdf_write_leaves_the_old_file_intact(tmp_path, sig):
    """Killed mid-write: the old file stays.  SIGTERM and SIGINT remove the temporary file;
    after SIGKILL (no code runs) only a hidden temporary named for the dead process may
    remain, and the next write into the directory removes it."""
    layout = _big_layout(tmp_path / "big.yaml")
    target = tmp_path / "out" / "result.nc"
    target.parent.mkdir()
    hits = 0
    seen = []  # (old file kept, exit code) of each try, for the message
    for _ in range(10):
        target.write_bytes(OLD)
        proc = _run_and_signal(layout, target, sig)
        # the signal may land after the rename (the write was quicker than the poll):
        # then the target is the complete new file, never anything in between
        kept = target.read_bytes() == OLD
        seen.append((kept, proc.returncode))
        assert kept or _is_complete_result(target)
        leftovers = sorted(p.name for p in target.parent.iterdir() if p != target)
        if sig != signal.SIGKILL:
            assert leftovers == []  # an orderly stop removes its temporary file
        else:
            owner = re.compile(
                rf"^\.result\.nc\.[0-9a-f]{{8}}-{proc.pid}-[0-9]+\.[0-9a-f]{{12}}\.part$"
            )
            assert all(owner.match(name) for name in leftovers), leftovers
            write_atomic(target, NEW, force=True)
            assert os.listdir(target.parent) == ["result.nc"]
        if kept and proc.returncode in (-sig, 128 + sig):
            hits += 1
            break
    assert hits, f"never caught the run while it was writing: (kept, exit code) {seen}"


def test_a_run_started_with_sigint_ignored_finishes_its_write(tmp_path):
    """``balance ... &`` from a script: the shell starts it with SIGINT ignored, so that a
    Ctrl-C meant for the foreground does not stop it.  balance keeps it ignored: a SIGINT
    sent while it writes changes nothing, and the run ends with the complete new file."""

    def ignore_sigint() -> None:
        signal.signal(signal.SIGINT, signal.SIG_IGN)

    layout = _big_layout(tmp_path / "big.yaml")
    target = tmp_path / "out" / "result.nc"
    target.parent.mkdir()
    target.write_bytes(OLD)
    proc = _run_and_signal(layout, target, signal.SIGINT, sigint=ignore_sigint)
    assert proc.returncode == 0
    assert _is_complete_result(target)
    assert os.listdir(target.parent) == ["result.nc"]


def _writing_chunks(directory: Path) -> bool:
    """True once a temporary Zarr store in ``directory`` holds a fourth chunk. The store
    can be renamed or removed while glob walks it; that is "not now", not an error."""
    try:
        return bool(list(directory.glob(".sweep.zarr.*.part/*/c/3")))
    except FileNotFoundError:
        return False


@needs("zarr", "zarr")
def test_terminated_zarr_sweep_keeps_the_old_store(tmp_path):
    """SIGTERM while a Zarr store is written (its chunks by zarr's thread pool): the run
    stops at the next chunk, when no thread writes, and leaves nothing behind."""
    target = tmp_path / "out" / "sweep.zarr"
    target.parent.mkdir()
    vary = ["--vary", "speed=1000rpm:8000rpm:200", "--vary", "conrod_length=130mm:160mm:100"]
    command = [sys.executable, "-m", "balance", "sweep", "inline-4", *vary, "--chunk-size", "250"]
    for _ in range(10):
        shutil.rmtree(target, ignore_errors=True)
        target.mkdir()
        (target / "zarr.json").write_bytes(OLD)  # a store balance may replace
        proc = subprocess.Popen(
            [*command, "-o", str(target), "--force"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        try:
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline and proc.poll() is None:
                if _writing_chunks(target.parent):
                    proc.send_signal(signal.SIGTERM)
                    break
                time.sleep(0.0002)
            proc.wait(timeout=120)
        finally:
            if proc.poll() is None:  # the test failed: leave no process to the next test
                proc.kill()
                proc.wait()
        assert os.listdir(target.parent) == ["sweep.zarr"]
        kept = os.listdir(target) == ["zarr.json"] and (target / "zarr.json").read_bytes() == OLD
        if kept and proc.returncode == 128 + signal.SIGTERM:
            break
        import xarray as xr

        with xr.open_zarr(target) as ds:  # else the run had finished: the whole new store
            assert ds.sizes["speed"] == 200 and ds.sizes["conrod_length"] == 100
    else:
        pytest.fail("never caught the run while it was writing")


def test_a_signal_during_a_directory_write_stops_it_at_a_checkpoint(tmp_path, monkeypatch):
    monkeypatch.setattr(atomic, "_STOP", [])
    target = tmp_path / "store.zarr"
    target.mkdir()
    (target / "zarr.json").write_bytes(OLD)
    assert not atomic.stop_at_checkpoint(143)  # no threaded write: the handler exits at once
    asked = []

    def write(tmp: Path) -> None:
        (tmp / "zarr.json").write_bytes(NEW)
        asked.append(atomic.stop_at_checkpoint(143))  # a signal while chunks are written
        asked.append(atomic.stop_at_checkpoint(143))  # a second one: end at once
        (tmp / "c").write_bytes(NEW)  # the writer goes on to its next checkpoint

    with pytest.raises(SystemExit) as stop:
        write_atomic_directory(target, write, force=True, is_replaceable=lambda _: True)
    assert stop.value.code == 143 and asked == [True, False]
    assert os.listdir(target) == ["zarr.json"] and (target / "zarr.json").read_bytes() == OLD
    assert os.listdir(tmp_path) == ["store.zarr"]


class _Interrupt(BaseException):
    """Stands for the KeyboardInterrupt or SystemExit a signal handler raises."""


def _interrupted_at(n: int, call: Callable[[], object]) -> bool:
    """Run ``call`` with an exception raised at the n-th bytecode executed in
    balance/io/atomic.py (where a signal handler can run); True if it was raised."""
    count = 0

    def local(frame, event, arg):
        nonlocal count
        if event == "opcode":
            count += 1
            if count == n:
                raise _Interrupt
        return local

    def calls(frame, event, arg):
        if frame.f_code.co_filename != atomic.__file__:
            return None
        frame.f_trace_opcodes = True
        return local

    sys.settrace(calls)
    try:
        call()
    except _Interrupt:
        return True
    finally:
        sys.settrace(None)
    return False


def _write_directory(target: Path) -> object:
    def write(tmp: Path) -> None:
        (tmp / "data").write_bytes(NEW)

    return write_atomic_directory(target, write, force=True, is_replaceable=lambda _: True)


WRITES: dict[str, Callable[[Path], object]] = {
    "file-by-writer": lambda p: write_atomic(p, lambda tmp: tmp.write_bytes(NEW), force=True),
    "file-from-bytes": lambda p: write_atomic(p, NEW, force=True),
    "directory-exchanged": _write_directory,
    "directory-moved-aside": _write_directory,  # where renameat2 cannot exchange
}


def _contents(path: Path) -> bytes | None:
    if path.is_dir():
        return (path / "data").read_bytes() if os.listdir(path) == ["data"] else b"?"
    return path.read_bytes() if path.exists() else None


@pytest.fixture
def scratch(tmp_path: Path) -> Iterator[Path]:
    """A directory in memory (tmpfs) where there is one: the test below renames and removes
    thousands of times, which on a disk's file system takes seconds instead of 0.2 s."""
    shm = Path("/dev/shm")
    if not (shm.is_dir() and os.access(shm, os.W_OK)):
        yield tmp_path
        return
    directory = Path(tempfile.mkdtemp(prefix="balance-test-", dir=shm))
    try:
        yield directory
    finally:
        shutil.rmtree(directory, ignore_errors=True)


@pytest.mark.parametrize("existing", [True, False])
@pytest.mark.parametrize("kind", sorted(WRITES))
def test_an_interrupt_at_any_bytecode_leaves_no_temporary(scratch, monkeypatch, kind, existing):
    """A signal handler's exception at every bytecode of a write in turn: the target is
    the old file or the new one, and nothing else is left once the process exits; no
    temporary exists that the process does not know of (no window between creating one
    and knowing its name, whatever threads the process has)."""
    if kind == "directory-moved-aside":
        monkeypatch.setattr(atomic, "_exchange", lambda a, b: False)
    atomic._owner(os.getpid())  # what a process reads about itself once, untraced
    target = scratch / "out" / "result"
    target.parent.mkdir()
    n = 0
    while True:
        n += 1
        if existing:
            if kind.startswith("directory"):
                target.mkdir(exist_ok=True)
                (target / "data").write_bytes(OLD)
            else:
                target.write_bytes(OLD)
        interrupted = _interrupted_at(n, lambda: WRITES[kind](target))
        # what is left at once is known to the process (interrupted in its own clean-up:
        # removed at exit); SystemExit and KeyboardInterrupt end the process, so exit
        left = set(os.listdir(target.parent)) - {"result"}
        assert left <= {p.name for p in atomic._PENDING}, n
        atomic._clean_up_at_exit()
        got = _contents(target)
        assert got in ((OLD, NEW) if existing else (None, NEW)), (n, got)
        assert os.listdir(target.parent) == (["result"] if got else []), n
        if not interrupted:
            assert got == NEW and not atomic._PENDING
            break
        if target.is_dir():
            shutil.rmtree(target)
        elif got is not None:
            target.unlink()
    assert n > 50  # every bytecode of the write was a place to interrupt it
    gc.collect()  # nothing left half-open by an interrupt (an unclosed file would warn here)


def test_orphans_of_killed_writes_are_removed_by_the_next_write(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", ""])
    dead.wait()
    key, pid, start = atomic._owner(os.getpid()).split("-")
    assert re.fullmatch(r"[0-9a-f]{8}", key) and int(pid) == os.getpid() and int(start) > 0
    orphan = tmp_path / f".result.nc.{key}-{dead.pid}-{start}.0123456789ab.part"
    orphan.write_bytes(b"half a netCDF file")
    orphan_store = tmp_path / f".store.zarr.{key}-{dead.pid}-7.0123456789ab.part"
    (orphan_store / "c").mkdir(parents=True)
    moved_aside = tmp_path / f".old.zarr.{key}-{dead.pid}-7.0123456789ab.old"
    (moved_aside / "previous").mkdir(parents=True)  # killed between two renames
    (moved_aside / "previous" / "zarr.json").write_bytes(OLD)
    alive = tmp_path / f".result.nc.{key}-{os.getpid()}-{start}.0123456789ab.part"
    alive.write_bytes(b"being written")
    foreign = tmp_path / f".result.nc.00000000-{dead.pid}-{start}.0123456789ab.part"
    foreign.write_bytes(b"another machine's")
    mine = tmp_path / ".result.nc.part"
    mine.write_bytes(b"not balance's")

    write_atomic(tmp_path / "result.nc", NEW)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [alive.name, foreign.name, mine.name, "old.zarr", "result.nc"]
    )
    assert (tmp_path / "old.zarr" / "zarr.json").read_bytes() == OLD  # put back


def test_failed_write_removes_the_temporary_file(tmp_path):
    target = tmp_path / "x.json"
    target.write_bytes(OLD)

    def boom(tmp: Path) -> None:
        tmp.write_text("half a file")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        write_atomic(target, boom, force=True)
    assert target.read_bytes() == OLD
    assert list(tmp_path.iterdir()) == [target]

    def boom_in_directory(tmp: Path) -> None:
        boom(tmp / "zarr.json")

    with pytest.raises(RuntimeError):
        write_atomic_directory(tmp_path / "new.zarr", boom_in_directory)
    assert list(tmp_path.iterdir()) == [target]


@pytest.mark.parametrize("data", [NEW, None])
def test_written_files_have_the_usual_permissions(tmp_path, data):
    umask = os.umask(0o027)
    try:
        target = write_atomic(tmp_path / "x", data if data else lambda p: p.write_bytes(NEW))
        again = write_atomic(target, data if data else lambda p: p.write_bytes(NEW), force=True)
    finally:
        os.umask(umask)
    assert target.read_bytes() == NEW
    assert again.stat().st_mode & 0o777 == 0o640


def test_targets_that_cannot_be_written(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        check_target(tmp_path / "missing" / "x.nc")
    with pytest.raises(InputError, match="is a directory"):
        check_target(tmp_path)
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError, match="is not a directory"):
        check_target(tmp_path / "file" / "x.nc")
    (tmp_path / "exists.nc").write_text("")
    with pytest.raises(InputError, match="file exists and replacing it was not asked for"):
        check_target(tmp_path / "exists.nc")
    assert check_target(tmp_path / "exists.nc", force=True) == tmp_path / "exists.nc"
