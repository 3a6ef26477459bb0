"""Output safety: whole files or nothing, even when a run is killed while it writes."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from balance.core.errors import InputError
from balance.io.atomic import check_target, write_atomic

OLD = b"the previous result, which must survive\n"


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


def _run_and_signal(layout: Path, target: Path, sig: int) -> bool:
    """Start a netCDF write and send ``sig`` as soon as its temporary file appears.

    Returns True if the signal arrived while the temporary file existed (mid-write)."""
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "balance",
            "analyse",
            str(layout),
            "-f",
            "netcdf",
            "--orders",
            "1-1000",
            "-o",
            str(target),
            "--force",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    hit = False
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if list(target.parent.glob(f".{target.name}.*.part")):
            proc.send_signal(sig)
            hit = True
            break
        time.sleep(0.0002)
    proc.wait(timeout=120)
    return hit


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killed_netcdf_write_leaves_the_old_file_intact(tmp_path, sig):
    layout = _big_layout(tmp_path / "big.yaml")
    target = tmp_path / "out" / "result.nc"
    target.parent.mkdir()
    for _ in range(10):
        target.write_bytes(OLD)
        if _run_and_signal(layout, target, sig):
            break
    else:
        pytest.fail("never caught the run while it was writing")
    assert target.read_bytes() == OLD
    leftovers = list(target.parent.glob("*.part"))
    if sig == signal.SIGTERM:
        assert leftovers == []  # an orderly stop removes its temporary file


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


def test_targets_that_cannot_be_written(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        check_target(tmp_path / "missing" / "x.nc")
    with pytest.raises(InputError, match="is a directory"):
        check_target(tmp_path)
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError, match="is not a directory"):
        check_target(tmp_path / "file" / "x.nc")
    (tmp_path / "exists.nc").write_text("")
    with pytest.raises(InputError, match="use --force"):
        check_target(tmp_path / "exists.nc")
    assert check_target(tmp_path / "exists.nc", force=True) == tmp_path / "exists.nc"
