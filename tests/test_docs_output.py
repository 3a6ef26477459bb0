"""The output the documentation shows is the program's output.

Every ```` ```console ```` block of ``docs/*.md`` and of the README whose ``$ balance ...``
command is followed by its output (the next fenced block, a ```` ```text ```` one, with only
prose between them) is run, and the output shown is compared with what the program prints,
line by line.  Only what must be is normalised: the terminal is 100 columns wide
(``COLUMNS=100``, as the tutorial says) and trailing spaces are dropped.  A line ``...``
in the output shown stands for lines left out (any number, none included); a block that
shows an excerpt starts or ends with it, so that every other line must be the program's.

The files the tutorial's commands read are made as the tutorial says, from its own text:
``my-inline-3.yaml`` is its YAML block, ``my-inline-4.yaml`` the built-in inline-4 in the
explicit form with the second cylinder's line edited as shown, ``my-inline-4-shafts.yaml``
the same with its ``balance:`` block appended.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]
FENCE = re.compile(r"^```(\w*)")


@dataclass(frozen=True)
class Shown:
    """A command of a console block and the output shown after it."""

    page: Path
    line: int  # of the console block's opening fence, 1-based
    command: str
    output: list[str]

    @property
    def name(self) -> str:
        return f"{self.page.name}:{self.line}"


def _blocks(text: str) -> list[tuple[int, str, list[str]]]:
    """The fenced blocks of a Markdown page: (opening line, info string, body lines), and a
    heading between blocks as ("#", ...) so that an output never belongs across one."""
    out: list[tuple[int, str, list[str]]] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if fence:
            j = i + 1
            while not lines[j].startswith("```"):
                j += 1
            out.append((i + 1, fence.group(1), lines[i + 1 : j]))
            i = j + 1
            continue
        if lines[i].startswith("#") or re.match(r"^\(\S+\)=$", lines[i]):
            out.append((i + 1, "#", []))
        i += 1
    return out


def _commands(body: list[str]) -> list[str]:
    """The ``$`` commands of a console block, continuation lines joined, comments kept out."""
    commands: list[str] = []
    pending = ""
    for raw in body:
        line = raw.rstrip()
        if pending:
            pending += " " + line.strip()
        elif line.startswith("$ "):
            pending = line[2:]
        else:
            continue
        if pending.endswith("\\"):
            pending = pending[:-1].rstrip()
            continue
        commands.append(pending)
        pending = ""
    return commands


def shown_outputs() -> list[Shown]:
    """Every ``$ balance`` command of a console block that is followed by its output."""
    found = []
    for page in PAGES:
        blocks = _blocks(page.read_text(encoding="utf-8"))
        for (line, info, body), after in zip(blocks, [*blocks[1:], None], strict=True):
            if info != "console" or after is None or after[1] != "text":
                continue
            commands = [c for c in _commands(body) if c.startswith("balance ")]
            assert len(commands) == 1, (
                f"{page.name}:{line}: a console block followed by output shows one balance "
                f"command, not {len(commands)}"
            )
            found.append(Shown(page, line, commands[0], after[2]))
    return found


SHOWN = shown_outputs()


def test_the_docs_show_outputs():
    """The pages show the outputs the tutorial walks through (not an empty search)."""
    assert len(SHOWN) >= 12
    assert {s.page.name for s in SHOWN} >= {"tutorial.md", "bearings.md"}


def _yaml_block(text: str, starts: str) -> str:
    """The body of the YAML block of a page whose first line starts with ``starts``."""
    for _, info, body in _blocks(text):
        if info == "yaml" and body and body[0].lstrip().startswith(starts):
            return "\n".join(body) + "\n"
    raise AssertionError(f"no yaml block starting with {starts!r}")


def _run(command: str, cwd: Path) -> str:
    """``command`` in a shell whose ``balance`` is this checkout's, 100 columns wide; a
    plain ``balance ...`` command (no pipe or redirection) in this process, through the
    command-line app, as the shell would give it (the same argument words, environment and
    directory): a fresh interpreter for each would spend most of its time importing."""
    if not set(command) & set("|<>;&$`*?"):
        return _run_here(command, cwd)
    bin_dir = cwd / ".bin"
    if not (bin_dir / "balance").exists():
        bin_dir.mkdir(exist_ok=True)
        shim = bin_dir / "balance"
        shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m balance "$@"\n')
        shim.chmod(0o755)
    env = {
        **os.environ,
        "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
        "COLUMNS": "100",
        "NO_COLOR": "1",
    }
    env.pop("FORCE_COLOR", None)
    done = subprocess.run(
        ["bash", "-c", f"set -o pipefail; {command}"],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, f"{command}: exit {done.returncode}\n{done.stderr}"
    return done.stdout


def _run_here(command: str, cwd: Path) -> str:
    from typer.testing import CliRunner

    from balance.cli import app

    words = shlex.split(command)
    assert words[0] == "balance"
    env = {"COLUMNS": "100", "NO_COLOR": "1", "FORCE_COLOR": None}
    before = Path.cwd()
    os.chdir(cwd)
    try:
        done = CliRunner().invoke(app, words[1:], env=env)
    finally:
        os.chdir(before)
    assert done.exit_code == 0, f"{command}: exit {done.exit_code}\n{done.output}"
    return done.stdout


def _tutorial_files(cwd: Path) -> None:
    """The files the tutorial's commands read, made as the tutorial says."""
    text = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
    (cwd / "my-inline-3.yaml").write_text(_yaml_block(text, "name: My inline-3"))
    expanded = _run("balance layout expand inline-4", cwd)
    edit = _yaml_block(text, "- {throw: 180 deg, bank: 0 deg, z: 90 mm,").strip()
    lines = expanded.splitlines()
    second = [i for i, line in enumerate(lines) if line.strip().startswith("- {throw:")][1]
    indent = lines[second][: len(lines[second]) - len(lines[second].lstrip())]
    lines[second] = indent + edit
    (cwd / "my-inline-4.yaml").write_text("\n".join(lines) + "\n")
    (cwd / "my-inline-4-shafts.yaml").write_text(expanded + _yaml_block(text, "balance:"))


def _matches(shown: list[str], printed: list[str]) -> bool:
    """Whether the output shown is the output printed: line by line, ``...`` standing for
    any run of lines (none included); without a leading (trailing) ``...`` the output shown
    starts (ends) where the printed one does."""
    segments: list[list[str]] = [[]]
    for line in shown:
        if line.strip() == "...":
            segments.append([])
        else:
            segments[-1].append(line)
    at = 0
    for n, segment in enumerate(segments):
        if not segment:
            continue
        anchored = n == 0
        last = n == len(segments) - 1
        starts = [at] if anchored else range(at, len(printed) - len(segment) + 1)
        for start in starts:
            if printed[start : start + len(segment)] == segment and (
                not last or start + len(segment) == len(printed)
            ):
                at = start + len(segment)
                break
        else:
            return False
    return True


def _lines(text: str) -> list[str]:
    lines = [line.rstrip() for line in text.splitlines()]
    while lines and not lines[-1]:
        lines.pop()
    return lines


@pytest.mark.parametrize("shown", SHOWN, ids=lambda s: s.name)
def test_docs_output_is_the_programs(shown, tmp_path):
    if shown.page.name == "tutorial.md":
        _tutorial_files(tmp_path)
    printed = _lines(_run(shown.command, tmp_path))
    expected = _lines("\n".join(shown.output))
    assert _matches(expected, printed), (
        f"{shown.name}: `{shown.command}` prints (COLUMNS=100):\n" + "\n".join(printed)
    )


def test_matching_rules():
    """``...`` stands for lines left out; without it the output shown is all of it."""
    printed = ["a", "b", "c", "d"]
    assert _matches(["a", "b", "c", "d"], printed)
    assert not _matches(["a", "b", "c"], printed)  # the end is missing
    assert not _matches(["b", "c", "d"], printed)  # the start is missing
    assert _matches(["a", "...", "d"], printed)
    assert _matches(["...", "b", "c", "..."], printed)
    assert _matches(["...", "c", "d"], printed)
    assert not _matches(["...", "c", "b", "..."], printed)
    assert not _matches(["a", "...", "x"], printed)
    assert _matches(["a", "b", "...", "c", "d"], printed)  # ... may stand for no line
