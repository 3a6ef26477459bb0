"""The documentation says what the program does: docs/cli.md against the typer app.

Every command, every option of every command and every plot kind must be described in
``docs/cli.md``: in the overview at the top (under ``balance COMMAND``) and in the
command's own section (``## `balance COMMAND```).  A command or option added to the program
without its documentation fails here.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import typer

import balance
from balance.cli import app
from balance.views.json import to_dict
from balance.views.plots import all_kinds

CLI_MD = Path(__file__).resolve().parents[1] / "docs" / "cli.md"
PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"
README = Path(__file__).resolve().parents[1] / "README.md"


def _commands():
    """(command path, click command) for every command of the app, groups walked."""
    root = typer.main.get_command(app)

    def walk(command, path):
        subcommands = getattr(command, "commands", None)
        if subcommands is None:
            yield " ".join(path), command
            return
        for name, sub in subcommands.items():
            yield from walk(sub, [*path, name])

    return list(walk(root, [])), root


COMMANDS, ROOT = _commands()


def _options(command) -> list[str]:
    return [
        name
        for param in command.params
        if param.param_type_name == "option"
        for name in (*param.opts, *param.secondary_opts)
    ]


def _text() -> str:
    return CLI_MD.read_text(encoding="utf-8")


def _overview() -> dict[str, str]:
    """The overview block: each ``balance COMMAND`` entry with its continuation lines."""
    block = _text().split("```text", 1)[1].split("```", 1)[0]
    entries: dict[str, str] = {}
    current = None
    for line in block.splitlines():
        if line.startswith("balance "):
            words = [w for w in line.split()[1:] if not w.startswith(("[", "-"))]
            name = " ".join(w for w in words[:2] if w.islower() and w.isalpha())
            command = next(
                (c for c, _ in sorted(COMMANDS, key=lambda c: -len(c[0])) if name.startswith(c)),
                name,
            )
            current = command
            entries[current] = entries.get(current, "") + line + "\n"
        elif current is not None:
            entries[current] += line + "\n"
    return entries


def _section(command: str) -> str:
    """The text of the section headed ``## `balance COMMAND``` (up to the next ``## ``)."""
    match = re.search(
        rf"^## `balance {re.escape(command)}`[^\n]*\n(.*?)(?=^## |\Z)", _text(), re.S | re.M
    )
    assert match, f"docs/cli.md has no section '## `balance {command}`'"
    return match.group(1)


def _named(text: str) -> set[str]:
    """Every option-like word inside the code spans and blocks of ``text``."""
    fenced = re.findall(r"```.*?```", text, re.S)  # code blocks first: their backticks
    spans = fenced + re.findall(r"`([^`]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    return {w for span in spans for w in re.findall(r"(?<![\w-])-{1,2}[a-z][a-z-]*", span)}


@pytest.mark.parametrize("command", [c for c, _ in COMMANDS])
def test_every_command_and_option_is_documented(command):
    options = _options(dict(COMMANDS)[command])
    overview = _overview()
    assert command in overview, f"the overview of docs/cli.md does not list 'balance {command}'"
    listed = set(re.findall(r"(?<![\w-])-{1,2}[a-z][a-z-]*", overview[command]))
    section = _named(_section(command))
    for option in options:
        assert option in listed, f"the overview of 'balance {command}' omits {option}"
        assert option in section, f"the section of 'balance {command}' does not describe {option}"


def test_global_options_are_documented():
    intro = _text().split("(cli-tables)=", 1)[0]
    for option in _options(ROOT):
        assert f"[{option}]" in _overview()[""], option  # balance [--debug] COMMAND ...
        assert f"`{option}`" in intro, option


def test_every_plot_kind_is_documented_under_its_file_name():
    section = _section("plot")
    described = re.findall(r"^\s*- (`[a-z_]+`(?:, `[a-z_]+`)*):", section, re.M)
    names = {n.strip("`") for line in described for n in line.split(", ")}
    kinds = set(all_kinds())
    assert names == kinds, names ^ kinds
    kind_help = next(p.help for p in dict(COMMANDS)["plot"].params if p.name == "kind")
    assert all(kind in kind_help for kind in kinds)


def test_every_json_block_is_documented():
    """Every top-level key of an analysis's JSON (with gas, bearings, mounts and crossheads) is
    named in the schema of docs/cli.md, and the schema names nothing the program does not
    write."""
    block = _text().split("## JSON output", 1)[1].split("```text", 1)[1].split("```", 1)[0]
    documented = set(re.findall(r'^  "(\w+)":', block, re.M))
    gas = to_dict(balance.compute_result("inline-4-gas", [1, 2]))
    mounted = to_dict(balance.compute_result("inline-4-mounts", [1, 2], bearings=True))
    crosshead = to_dict(balance.compute_result("marine-crosshead-6", [1, 2]))
    written = set(gas) | set(mounted) | set(crosshead) | {"balance_factor_study"}
    assert documented == written, documented ^ written
    assert "not yet produced" not in _text() and "refuses a `gas:`" not in _text()


def test_docs_extra_and_how_to_build_the_docs():
    """A ``docs`` extra with what docs/conf.py loads, and the README says how to build."""
    import tomllib

    extras = tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]
    names = {re.split(r"[<>=\[ ]", req, maxsplit=1)[0] for req in extras["docs"]}
    assert {"sphinx", "myst-parser", "numpydoc"} <= names
    conf = (CLI_MD.parent / "conf.py").read_text()
    for extension in re.findall(r'^\s*"([\w.]+)",$', conf, re.M):
        if "." not in extension and extension != "gallery":  # sphinx.ext.* ship with sphinx
            assert extension.replace("_", "-") in names, extension
    readme = README.read_text()
    assert readme.startswith(
        "# balance\n\n```sh\npython3 -m pip install . && balance analyse inline-4\n"
        "python3 -m pip install '.[test]' && python3 -m pytest\n```\n"
    )
    development = readme.split("## Development", 1)[1]
    assert "'.[docs]'" in development and "sphinx" in development


def _requirement_names(requirements: list[str]) -> set[str]:
    return {re.split(r"[<>=\[ ]", req, maxsplit=1)[0] for req in requirements}


#: What only a developer needs: the docs, the optional back ends, lint and types, a browser.
DEV_ONLY = {"sphinx", "myst-parser", "numpydoc", "playwright", "dask", "zarr", "mypy", "ruff"}


def test_the_test_extra_is_only_what_the_tests_need():
    """``test`` installs pytest and its plugins (``-n`` and ``--mpl`` of addopts),
    hypothesis, mpmath and scipy (the torsion validation's independent references), none of
    Sphinx, Playwright, Dask, Zarr, mypy or ruff; ``dev`` is
    ``test`` with ``docs``, ``zarr``, ``distributed``, Playwright, ruff and mypy.  The
    README's set-up commands stay two, and .ci/run runs its test command as written."""
    import tomllib

    extras = tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]
    test = _requirement_names(extras["test"])
    assert test == {"pytest", "pytest-xdist", "pytest-mpl", "hypothesis", "mpmath", "scipy"}
    assert not test & DEV_ONLY
    assert "balance[test,docs,zarr,distributed]" in extras["dev"]
    assert {"playwright", "ruff", "mypy", "types-PyYAML"} <= _requirement_names(extras["dev"])
    readme = README.read_text()
    setup = readme.split("```sh\n", 1)[1].split("```", 1)[0].splitlines()
    assert setup == [
        "python3 -m pip install . && balance analyse inline-4",
        "python3 -m pip install '.[test]' && python3 -m pytest",
    ]
    ci = (README.parent / ".ci" / "run").read_text()
    assert "python3 -m pip install '.[test]' && python3 -m pytest\n" in ci
    assert ci.index("pip install '.[dev]'") < ci.index("pip install '.[test]'")


#: The tests that need a package of ``dev`` only, and the package.
OPTIONAL_TESTS = {
    "tests/test_sweep.py::test_dask_cluster_gives_identical_result": "distributed",
    "tests/test_sweep.py::test_zarr_store_is_the_sweep_dataset": "zarr",
    "tests/test_sweep.py::test_zarr_write_that_fails_keeps_the_old_store": "zarr",
    "tests/test_sweep.py::test_sweep_refuses_to_replace_a_directory_that_is_not_a_store": "zarr",
    "tests/test_outputs_cli.py::test_sweep_summary_speed_in_rpm_and_attributes": "zarr",
    "tests/test_output.py::test_terminated_zarr_sweep_keeps_the_old_store": "zarr",
    "tests/test_report.py::test_report_renders_in_a_headless_browser": "playwright",
}


def test_tests_of_optional_packages_skip_only_when_they_are_absent(tmp_path):
    """With the packages of ``dev`` absent (as after ``pip install '.[test]'``), the tests
    that need one skip, naming it; where it is installed, their marker does not skip."""
    import importlib.util
    import os
    import subprocess
    import sys

    from helpers import needs

    for module in set(OPTIONAL_TESTS.values()):
        installed = importlib.util.find_spec(module) is not None
        assert needs(module, "dev").args[0] is not installed
    blocker = tmp_path / "absent_dev_packages.py"
    modules = ("dask", "distributed", "zarr", "playwright", "sphinx", "numpydoc", "mypy")
    blocker.write_text("import sys\n" + "".join(f"sys.modules[{m!r}] = None\n" for m in modules))
    root = README.parent
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(root)])}
    options = ["-q", "-n", "0", "-p", "absent_dev_packages", "-p", "no:cacheprovider", "-rs"]
    done = subprocess.run(
        [sys.executable, "-m", "pytest", *options, *OPTIONAL_TESTS],
        cwd=root,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout[-3000:]
    assert f"{len(OPTIONAL_TESTS)} skipped" in done.stdout, done.stdout[-3000:]
    for module in set(OPTIONAL_TESTS.values()):
        assert f"needs {module}, not installed" in done.stdout
