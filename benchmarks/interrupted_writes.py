"""Stress test of interrupted writes: kill ``balance`` at random moments, count what is left.

Runs real commands (``balance analyse ... --format netcdf``, ``--format json``, ``balance
sweep`` to netCDF and to Zarr, ``balance plot``) over and over, each time with the target
holding a sentinel "previous result", and sends SIGKILL, SIGTERM or SIGINT either after a
random delay anywhere in the run or at a random moment after the process first holds a
file open in the output directory (during the write).  Meanwhile ``--load`` processes keep
every core busy.  After each kill it checks the output directory:

* every target is either the sentinel (the old file, untouched) or byte for byte the
  complete result of an uninterrupted run (Zarr: the same Dataset); anything else,
  including a missing target, is a *corrupted* target;
* nothing else is visible: any other non-hidden file is a *stray* file;
* hidden temporaries (``.<target>.<owner>.<random>.part``): none may be left after
  SIGTERM or SIGINT; after SIGKILL they are counted, and the next write into the
  directory must remove them (checked after every run that completed, and at the end).

A fresh interpreter per run spends most of its time importing, so most runs (all but
``--spawn`` of them) are ``balance.cli.main()`` in a process forked from a server that
has imported balance and its libraries (``multiprocessing``'s forkserver); each such
child first starts an idle thread, as numpy's OpenBLAS does in a fresh process, so that a
signal sent to the process can land on a thread other than the main one.  The other runs
are ``python -m balance`` exactly as a user starts it.

    python benchmarks/interrupted_writes.py --kills 600 --load 2 --jobs 2

Exit status 0 when nothing was corrupted, nothing stray, no temporary survived a SIGTERM
or SIGINT, and none survived a later completed write; 1 otherwise.  ``--repo`` runs
another checkout's code (to measure an older version).
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import json
import multiprocessing
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

SENTINEL = b"the previous result, which must survive\n"
SIGNALS = {"KILL": signal.SIGKILL, "TERM": signal.SIGTERM, "INT": signal.SIGINT}
FORCE = ["--force"]
SWEEP = ["--vary", "speed=1000rpm:8000rpm:200", "--vary", "conrod_length=130mm:160mm:100"]
ZARR = "{out}/sweep.zarr"
SMALL_SWEEP = ["--vary", "speed=1000rpm:8000rpm:50", "--vary", "conrod_length=130mm:160mm:40"]


@dataclass
class Scenario:
    name: str
    args: list[str]  # the command after ``balance``; {out} is the output directory
    targets: list[str]  # file or directory names in {out}
    directory: bool = False  # the target is a directory (Zarr)
    weight: int = 1
    #: when to send the signal: any moment of the run, or while it holds a file open in
    #: the output directory (a write of a few bytes is over before the poll sees it)
    modes: tuple[str, ...] = ("anytime", "in-write", "in-write")


SCENARIOS = [
    Scenario(
        "analyse-netcdf",
        ["analyse", "v8-crossplane", "--format", "netcdf", "-o", "{out}/result.nc", *FORCE],
        ["result.nc"],
        weight=2,
    ),
    Scenario(
        "analyse-big-netcdf",
        ["analyse", "{big}", "--orders", "1-1000", "-f", "netcdf", "-o", "{out}/big.nc", *FORCE],
        ["big.nc"],
        weight=2,
    ),
    Scenario(
        "analyse-json",
        ["analyse", "v12-60", "--format", "json", "-o", "{out}/result.json", *FORCE],
        ["result.json"],
        modes=("anytime",),
    ),
    Scenario(
        "sweep-netcdf",
        ["sweep", "inline-4", *SWEEP, "--chunk-size", "500", "-o", "{out}/sweep.nc", *FORCE],
        ["sweep.nc"],
        weight=2,
    ),
    Scenario(
        "sweep-zarr",
        ["sweep", "inline-4", *SMALL_SWEEP, "--chunk-size", "250", "-o", ZARR, *FORCE],
        ["sweep.zarr"],
        directory=True,
    ),
    Scenario(
        "plot-png",
        ["plot", "inline-4", "-k", "locus", "-k", "spectrum", "-o", "{out}", *FORCE],
        ["inline-4-locus.png", "inline-4-spectrum.png"],
    ),
]


def big_layout(path: Path, n: int = 256) -> Path:
    """256 cylinders: with 1000 orders its netCDF write takes a while (as in the test)."""
    rng = random.Random(7)
    rows = "\n".join(
        f"  - {{throw: {rng.uniform(0, 360):.3f} deg, bank: {rng.uniform(-60, 60):.3f} deg, "
        f"z: {90 * i} mm}}"
        for i in range(n)
    )
    path.write_text(
        "name: big\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\ncylinders:\n" + rows + "\n"
    )
    return path


def is_temporary(name: str) -> bool:
    return name.startswith(".") and (name.endswith(".part") or name.endswith(".old"))


@functools.cache
def zarr_dataset(reference: Path) -> Any:
    import xarray as xr

    with xr.open_zarr(reference) as ds:
        return ds.load()


def same_zarr(path: Path, reference: Path) -> bool:
    import xarray as xr

    try:
        with xr.open_zarr(path) as got:
            return bool(got.load().identical(zarr_dataset(reference)))
    except Exception:
        return False


def open_in(pid: int, directory: str) -> bool:
    """Does process ``pid`` hold a file open in ``directory`` (its write has begun)?"""
    try:
        fds = os.listdir(f"/proc/{pid}/fd")
    except OSError:
        return False
    for fd in fds:
        try:
            if os.readlink(f"/proc/{pid}/fd/{fd}").startswith(directory):
                return True
        except OSError:
            pass
    return False


# --------------------------------------------------------------------------- processes


def warm_up() -> None:
    """In the fork server: import and initialise, once, what the runs use (xarray finds
    its backends on the first write, matplotlib its fonts on the first figure)."""
    from balance.cli import main

    with tempfile.TemporaryDirectory() as d:
        for argv in (
            ["analyse", "inline-4", "-f", "netcdf", "-o", f"{d}/a.nc"],
            ["analyse", "inline-4", "-f", "json", "-o", f"{d}/a.json"],
            ["sweep", "inline-4", "--vary", "speed=1000rpm,2000rpm", "-o", f"{d}/s.zarr"],
            ["plot", "inline-4", "-k", "locus", "-o", d],
        ):
            sys.argv = ["balance", *argv]
            with contextlib.suppress(SystemExit), contextlib.redirect_stderr(io.StringIO()):
                main()
    # main() set its handlers; a child must start as a fresh interpreter does
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.default_int_handler)


if __name__ == "interrupted_writes" and os.environ.pop("INTERRUPTED_WRITES_WARM_UP", ""):
    warm_up()  # in the fork server, which imports this module by name (preloaded)


def run_cli(argv: list[str]) -> None:
    """A forked ``balance`` run: the command line's main, then what interpreter exit does."""
    import atexit

    code: Any = 0
    try:  # (a signal may come at any moment, this one included)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        threading.Thread(target=time.sleep, args=(3600,), daemon=True).start()  # as OpenBLAS
        sys.argv = ["balance", *argv]
        from balance.cli import main

        main()
    except SystemExit as exc:
        code = exc.code
    except KeyboardInterrupt:
        code = 130
    finally:
        # what the interpreter does at exit: wait for other threads, then atexit
        threading._shutdown()  # type: ignore[attr-defined]
        atexit._run_exitfuncs()
    os._exit(code if isinstance(code, int) else 1)


class Forked:
    """A forked run, with the part of the Popen interface used here."""

    def __init__(self, context: Any, argv: list[str]) -> None:
        self.process = context.Process(target=run_cli, args=(argv,))
        self.process.start()
        self.pid: int = self.process.pid

    def poll(self) -> int | None:
        return self.process.exitcode

    def send_signal(self, sig: int) -> None:
        with contextlib.suppress(ProcessLookupError):  # it has just ended
            os.kill(self.pid, sig)

    def wait(self) -> int:
        self.process.join()
        return self.returncode

    @property
    def returncode(self) -> int:
        code = self.process.exitcode
        assert code is not None
        return code


@dataclass
class Prepared:
    scenario: Scenario
    reference: dict[str, object]  # target name -> its bytes (or a Zarr path)
    duration: float  # an uninterrupted run, seconds
    write_start: float  # when it first held a file in the output directory


@dataclass
class Tally:
    counts: Counter[str] = field(default_factory=Counter)
    problems: list[str] = field(default_factory=list)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def add(self, key: str, n: int = 1) -> None:
        with self.lock:
            self.counts[key] += n

    def problem(self, text: str) -> None:
        with self.lock:
            self.problems.append(text)
            print("PROBLEM:", text, file=sys.stderr, flush=True)


class Runner:
    def __init__(self, repo: Path, root: Path) -> None:
        self.env = dict(os.environ, PYTHONPATH=str(repo), PYTHONDONTWRITEBYTECODE="1")
        self.root = root
        self.big = big_layout(root / "big.yaml")
        sys.path.insert(0, str(repo))
        self.context = multiprocessing.get_context("forkserver")
        # the fork server finds the preloaded modules through PYTHONPATH (Python 3.11's
        # ignores the parent's sys.path, and never imports a preloaded "__main__")
        here = str(Path(__file__).resolve().parent)
        os.environ["PYTHONPATH"] = os.pathsep.join([str(repo), here])
        os.environ["INTERRUPTED_WRITES_WARM_UP"] = "1"
        self.context.set_forkserver_preload(["interrupted_writes"])

    def argv(self, scenario: Scenario, out: Path) -> list[str]:
        fill = {"out": str(out), "big": str(self.big)}
        return [a.format(**fill) for a in scenario.args]

    def start(self, scenario: Scenario, out: Path, spawn: bool) -> Any:
        if not spawn:
            return Forked(self.context, self.argv(scenario, out))
        return subprocess.Popen(
            [sys.executable, "-m", "balance", *self.argv(scenario, out)],
            env=self.env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )

    def prepare(self, scenario: Scenario) -> Prepared:
        out = self.root / "reference" / scenario.name
        out.mkdir(parents=True)
        self.start(scenario, out, spawn=False).wait()  # warm the fork server
        t0 = time.monotonic()
        proc = self.start(scenario, out, spawn=False)
        write_start = None
        while proc.poll() is None:
            if write_start is None and open_in(proc.pid, str(out) + "/"):
                write_start = time.monotonic() - t0
            time.sleep(0.0005)
        duration = time.monotonic() - t0
        if proc.returncode != 0:
            done = subprocess.run(
                [sys.executable, "-m", "balance", *self.argv(scenario, out)],
                env=self.env,
                capture_output=True,
            )
            raise SystemExit(f"{scenario.name}: the uninterrupted run failed: {done.stderr!r}")
        reference: dict[str, object] = {}
        for name in scenario.targets:
            path = out / name
            reference[name] = path if scenario.directory else path.read_bytes()
        left = [p.name for p in out.iterdir() if p.name not in scenario.targets]
        if left:
            raise SystemExit(f"{scenario.name}: an uninterrupted run left {left}")
        return Prepared(scenario, reference, duration, write_start or 0.0)

    @staticmethod
    def reset(prepared: Prepared, out: Path) -> None:
        """Put the sentinel "previous result" in place of every target."""
        for name in prepared.scenario.targets:
            path = out / name
            if path.is_dir():
                shutil.rmtree(path)
            if prepared.scenario.directory:
                path.mkdir(exist_ok=True)
                (path / "zarr.json").write_bytes(SENTINEL)  # a "store" balance may replace
            else:
                path.write_bytes(SENTINEL)

    @staticmethod
    def check(prepared: Prepared, out: Path) -> tuple[int, int, int, list[str]]:
        """(old targets, new targets, corrupted targets, temporaries); stray files raise."""
        old = new = bad = 0
        names = {p.name for p in out.iterdir()}
        temporaries = sorted(n for n in names if is_temporary(n))
        stray = names - set(prepared.scenario.targets) - set(temporaries)
        for name in prepared.scenario.targets:
            path = out / name
            if not path.exists():
                bad += 1
                continue
            if prepared.scenario.directory:
                if [p.name for p in path.iterdir()] == ["zarr.json"] and (
                    (path / "zarr.json").read_bytes() == SENTINEL
                ):
                    old += 1
                elif same_zarr(path, prepared.reference[name]):  # type: ignore[arg-type]
                    new += 1
                else:
                    bad += 1
            else:
                data = path.read_bytes()
                if data == SENTINEL:
                    old += 1
                elif data == prepared.reference[name]:
                    new += 1
                else:
                    bad += 1
        if stray:
            raise AssertionError(f"stray files {sorted(stray)}")
        return old, new, bad, temporaries


def kill_once(
    runner: Runner, prepared: Prepared, out: Path, rng: random.Random, spawn: bool, tally: Tally
) -> None:
    scenario = prepared.scenario
    sig_name = rng.choice(["KILL", "KILL", "TERM", "INT"])
    mode = rng.choice(scenario.modes)
    runner.reset(prepared, out)
    before = [n for n in os.listdir(out) if is_temporary(n)]
    proc = runner.start(scenario, out, spawn)
    t0 = time.monotonic()
    if mode == "anytime":
        # a fresh interpreter spends about 0.8 s importing before the forked run's start
        delay = rng.uniform(0.0, prepared.duration * 1.1 + (0.8 if spawn else 0.0))
        while proc.poll() is None and time.monotonic() - t0 < delay:
            time.sleep(0.001)
    else:
        while proc.poll() is None and not open_in(proc.pid, str(out) + "/"):
            time.sleep(0.0003)
        delay = rng.uniform(0.0, max(prepared.duration - prepared.write_start, 0.01))
        t1 = time.monotonic()
        while proc.poll() is None and time.monotonic() - t1 < delay:
            time.sleep(0.0005)
    if proc.poll() is None:
        proc.send_signal(SIGNALS[sig_name])
    rc = proc.wait()
    key = f"{scenario.name} SIG{sig_name}"
    tally.add("runs")
    tally.add(f"runs {'spawned' if spawn else 'forked'}")
    tally.add(f"runs of {key}")
    try:
        old, new, bad, temporaries = runner.check(prepared, out)
    except AssertionError as exc:
        tally.problem(f"{key} {mode}: {exc}")
        tally.add("stray files")
        return
    completed = rc == 0
    tally.add("completed before the signal" if completed else "killed")
    if not completed and old == len(scenario.targets):
        tally.add("killed, every target still the old file")
    if not completed and new:
        tally.add("killed, some target already the complete new file")
    if bad:
        tally.add("corrupted targets", bad)
        tally.problem(f"{key} {mode} rc={rc}: {bad} corrupted target(s)")
    fresh = [n for n in temporaries if n not in before]
    if temporaries and (completed or fresh):
        if completed:
            tally.add("temporaries surviving a completed write", len(temporaries))
            tally.problem(f"{key}: a completed write left {temporaries}")
        elif sig_name == "KILL":
            tally.add("hidden temporaries left by SIGKILL", len(fresh))
            tally.add(f"left by SIGKILL in {scenario.name}", len(fresh))
        else:
            tally.add(f"temporaries left by SIG{sig_name}", len(fresh))
            tally.problem(f"{key} {mode} rc={rc}: SIG{sig_name} left {fresh}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kills", type=int, default=600, help="runs to interrupt in all")
    parser.add_argument("--spawn", type=float, default=0.1, help="fraction of fresh processes")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time")
    parser.add_argument("--load", type=int, default=os.cpu_count() or 2, help="CPU burners")
    parser.add_argument("--seconds", type=float, default=240.0, help="stop starting runs then")
    parser.add_argument("--seed", type=int, default=20261124)
    parser.add_argument("--repo", type=Path, default=Path(__file__).resolve().parents[1])
    parser.add_argument("--json", type=Path, help="also write the counts here")
    args = parser.parse_args()

    # children get the default SIGINT (a shell may have started this with SIGINT ignored)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    start = time.monotonic()
    root = Path(tempfile.mkdtemp(prefix="interrupted-writes-"))
    tally = Tally()
    burners: list[subprocess.Popen[bytes]] = []
    try:
        runner = Runner(args.repo.resolve(), root)
        prepared = [runner.prepare(s) for s in SCENARIOS]
        for p in prepared:
            print(
                f"{p.scenario.name}: uninterrupted {p.duration:.2f} s "
                f"(forked), writing from {p.write_start:.2f} s",
                flush=True,
            )
        stop = start + args.seconds
        until = args.seconds + 60
        code = f"import time\nt = time.monotonic() + {until}\nwhile time.monotonic() < t: pass"
        burners = [subprocess.Popen([sys.executable, "-c", code]) for _ in range(args.load)]
        weighted = [p for p in prepared for _ in range(p.scenario.weight)]
        plan = [random.Random(args.seed + i) for i in range(args.kills)]
        lock = threading.Lock()

        def worker(w: int) -> None:
            outs = {p.scenario.name: root / f"job{w}" / p.scenario.name for p in prepared}
            for out in outs.values():
                out.mkdir(parents=True)
            while True:
                with lock:
                    if not plan or time.monotonic() > stop:
                        return
                    rng = plan.pop(0)
                p = rng.choice(weighted)
                spawn = rng.random() < args.spawn
                kill_once(runner, p, outs[p.scenario.name], rng, spawn, tally)
                done = tally.counts["runs"]
                if done % 50 == 0:
                    print(f"{done} runs, {time.monotonic() - start:.0f} s", flush=True)

        threads = [threading.Thread(target=worker, args=(w,)) for w in range(args.jobs)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for b in burners:
            b.terminate()
        # the next completed write into each directory removes what SIGKILL left behind
        for w in range(args.jobs):
            for p in prepared:
                out = root / f"job{w}" / p.scenario.name
                runner.reset(p, out)
                rc = runner.start(p.scenario, out, spawn=True).wait()
                _, new, bad, temporaries = runner.check(p, out)
                if bad or rc != 0 or new != len(p.scenario.targets) or temporaries:
                    tally.problem(
                        f"{p.scenario.name}: final write: exit {rc}, {new} new, "
                        f"{bad} corrupted, left {temporaries}"
                    )
                    tally.add("temporaries surviving a completed write", len(temporaries))
    finally:
        for b in burners:
            b.kill()
            b.wait()
        shutil.rmtree(root, ignore_errors=True)

    elapsed = time.monotonic() - start
    counts = dict(sorted(tally.counts.items()))
    print(
        f"\n{counts.get('runs', 0)} interrupted runs in {elapsed:.0f} s "
        f"({args.jobs} at a time, {args.load} CPU burners)"
    )
    for key, value in counts.items():
        if not key.startswith(("runs of ", "left by SIGKILL in ")):
            print(f"  {key}: {value}")
    print("  hidden temporaries left by SIGKILL (removed by the next write), per scenario:")
    for scenario in SCENARIOS:
        kills = counts.get(f"runs of {scenario.name} SIGKILL", 0)
        left = counts.get(f"left by SIGKILL in {scenario.name}", 0)
        print(f"    {scenario.name}: {left} after {kills} kills")
    print("  per scenario and signal:")
    for key, value in counts.items():
        if key.startswith("runs of "):
            print(f"    {key[8:]}: {value}")
    for key in ("corrupted targets", "stray files", "temporaries surviving a completed write"):
        print(f"  {key}: {counts.get(key, 0)}")
    for sig in ("TERM", "INT"):
        print(f"  temporaries left by SIG{sig}: {counts.get(f'temporaries left by SIG{sig}', 0)}")
    print(f"  problems: {len(tally.problems)}")
    if args.json:
        args.json.write_text(json.dumps({"seconds": elapsed, "counts": counts}, indent=1))
    return 1 if tally.problems else 0


if __name__ == "__main__":
    sys.exit(main())
