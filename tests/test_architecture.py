"""The package's layers, read from the source: what may import what, and no cycles.

``balance/core`` is the physics on numpy and the standard library; ``io`` reads inputs,
``views`` writes outputs, ``studies`` runs many analyses; ``api`` and the command line
(the package ``cli``) sit on top.
Arrows point down only (docs/architecture.md).  Every import counts: module level, inside
functions and under ``TYPE_CHECKING``.
"""

from __future__ import annotations

import ast
import functools
import re
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "balance"

#: Layer of each part of the package: a module may import its own layer or lower ones.
RANK = {"core": 0, "io": 1, "views": 2, "studies": 2, "api": 3, "cli": 4, "__main__": 5}
#: Third-party packages each layer may import (besides numpy and the standard library).
ALLOWED = {
    "core": set(),
    "io": {"pint", "pydantic", "pydantic_core", "yaml"},
    "views": {"xarray", "pandas", "matplotlib", "rich", "netCDF4", "zarr"},
    "studies": {"xarray", "pandas", "dask", "distributed", "zarr", "netCDF4"},
    "api": {"xarray"},
    "cli": {"typer", "click", "rich", "distributed"},
    "__main__": set(),
}
#: Never in io, whatever else it may use.
NOT_IN_IO = {"xarray", "matplotlib", "typer", "rich", "pandas"}


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every module the file imports (absolute names), at any depth of the file."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                module = ".".join([*base, node.module] if node.module else base)
            else:
                module = node.module or ""
            found.add(module)
            # "from balance.core import kinematics" imports balance.core.kinematics
            for alias in node.names:
                candidate = f"{module}.{alias.name}"
                if (PACKAGE.parent / Path(*candidate.split("."))).with_suffix(".py").is_file():
                    found.add(candidate)
    return found


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Each module's imports (read when a test first asks: collecting the tests reads none)."""
    return {name: _imports(path) for name, path in MODULES.items()}


def _layer(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "balance" or len(parts) < 2:
        return None
    return parts[1] if parts[1] in RANK else None


def test_the_layers_are_the_folders():
    for layer in ("core", "io", "views", "studies", "cli"):
        assert (PACKAGE / layer / "__init__.py").is_file(), layer
    loose = {p.stem for p in PACKAGE.glob("*.py")} - {"__init__", "__main__", "_version"}
    assert loose == {"api"}, f"modules outside the layers: {sorted(loose)}"


#: The command line's own modules: the application (``balance.cli``), what its commands
#: share, and the commands by job.
CLI_COMMANDS = {"balance.cli.analysis", "balance.cli.studies", "balance.cli.layouts"}


def test_the_command_line_is_the_application_over_its_commands():
    """Only the application (``balance.cli``) puts the commands together: a module of
    commands imports ``balance.cli.common`` and no other module of the command line, and
    ``common`` imports none (so none imports the application, which imports them all)."""
    cli = {m for m in MODULES if m == "balance.cli" or m.startswith("balance.cli.")}
    assert cli == {"balance.cli", "balance.cli.common", *CLI_COMMANDS}, sorted(cli)
    assert {"balance.cli.common", *CLI_COMMANDS} <= _graph()["balance.cli"]
    for module in sorted(cli - {"balance.cli"}):
        own = {i for i in _graph()[module] if i == "balance.cli" or i.startswith("balance.cli.")}
        allowed = {"balance.cli.common"} if module in CLI_COMMANDS else set()
        assert own <= allowed, f"{module} imports {sorted(own - allowed)}"


@pytest.mark.parametrize("module", sorted(m for m in MODULES if _layer(m)))
def test_imports_point_down(module):
    layer = _layer(module)
    assert layer is not None
    for imported in _graph()[module]:
        top = imported.split(".")[0]
        if top == "balance":
            target = _layer(imported)
            if imported in {"balance", "balance._version"}:
                assert imported == "balance._version" or layer == "__main__", (
                    f"{module} imports the package root (import balance._version instead)"
                )
                continue
            assert target is not None, f"{module} imports {imported}, outside the layers"
            assert RANK[target] <= RANK[layer], f"{module} ({layer}) imports up: {imported}"
            if RANK[target] == RANK[layer]:
                assert target == layer, f"{module} ({layer}) imports its sibling {imported}"
        elif top in sys.stdlib_module_names or top in {"numpy", "__future__"}:
            continue
        else:
            assert top in ALLOWED[layer], f"{module} ({layer}) imports {imported}"
            if layer == "io":
                assert top not in NOT_IN_IO, f"{module} imports {imported}"


def test_core_is_numpy_and_the_standard_library_only():
    for module in (m for m in MODULES if _layer(m) == "core"):
        for imported in _graph()[module]:
            top = imported.split(".")[0]
            assert (
                top in sys.stdlib_module_names
                or top in {"numpy", "__future__"}
                or imported.startswith("balance.core")
            ), f"{module} imports {imported}"


#: A command-line option in a text: ``--force``, ``--vary`` (not ``---`` or ``a--b``).
FLAG = re.compile(r"(?<![\w-])--[a-z]")


def _texts(path: Path) -> list[tuple[int, str]]:
    """The string constants of a module that are not docstrings: what it may print."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    documented = (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, documented)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    return [
        (node.lineno, node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and id(node) not in docstrings
    ]


@pytest.mark.parametrize("layer", ["core", "io", "studies"])
def test_the_library_names_settings_not_command_line_options(layer):
    """core, io and studies are called from Python too: their messages name a quantity or a
    parameter (``vary:``, ``(force)``); the command line puts its options in their place
    (balance.cli.common.options_named, guarded)."""
    found = [
        f"{path.relative_to(PACKAGE.parent)}:{line}: {text!r}"
        for path in sorted((PACKAGE / layer).rglob("*.py"))
        for line, text in _texts(path)
        if FLAG.search(text)
    ]
    assert not found, found


def test_the_flag_check_sees_a_message_and_not_a_docstring(tmp_path):
    module = tmp_path / "m.py"
    module.write_text('"""Use ``--force``."""\n\nTEXT = f"{1}: use --force"\nRULE = "----"\n')
    assert [text for _, text in _texts(module) if FLAG.search(text)] == [": use --force"]


def test_no_import_cycle():
    internal = {m: {i for i in _graph()[m] if i in MODULES and i != m} for m in MODULES}
    # the package __init__ is imported by every submodule's import machinery; its own
    # imports (lazy attributes) are not edges of the layered graph
    internal["balance"] = {i for i in internal["balance"] if i == "balance._version"}
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(internal[node]):
            if state.get(nxt) == 1:
                cycle = [*stack[stack.index(nxt) :], nxt]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for module in sorted(internal):
        if module not in state:
            visit(module)


def test_the_checker_sees_a_cycle_and_an_upward_import(tmp_path):
    """The rules above could pass by reading nothing: show that they read imports."""
    assert "balance.core.engine" in _graph()["balance.core.analysis"]
    assert "balance.core.kinematics" in _graph()["balance.core.analysis"]
    fake = tmp_path / "balance" / "core" / "fake.py"
    fake.parent.mkdir(parents=True)
    fake.write_text("from balance.views import table\nimport xarray\n")
    global PACKAGE
    saved = PACKAGE
    PACKAGE = tmp_path / "balance"
    try:
        assert _imports(fake) >= {"balance.views", "xarray"}
    finally:
        PACKAGE = saved


def test_the_package_offers_what_the_api_offers():
    """``import balance`` offers api.py's names and the error types, each loaded lazily
    from where it is defined."""
    import balance
    import balance.api
    from balance.core import errors

    lazy = balance._LAZY
    assert set(balance.__all__) == {"__version__", *lazy}
    assert {n for n, m in lazy.items() if m == "balance.api"} == set(balance.api.__all__)
    assert {n for n, m in lazy.items() if m != "balance.api"} <= set(errors.__all__)
    for name in lazy:
        assert getattr(balance, name) is getattr(sys.modules[lazy[name]], name)
