"""The package's shape, read from its source: each concern in a few files, no module too
long, test oracles in the tests, the package citing its own docs, and every public function
documenting its parameters (docs/architecture.md, "Concerns as sections")."""

from __future__ import annotations

import ast
import functools
import io
import re
import tokenize
from pathlib import Path
from typing import NamedTuple

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "balance"
TESTS = Path(__file__).resolve().parent

#: Concerns beyond the free forces, as their names appear in identifiers.
CONCERNS = ("bearing", "mount", "torsion", "dynamic", "crankshaft", "crosshead")
#: The files (modules) of the package whose identifiers may name one concern: its physics
#: (one or two core modules), its reader, its views, the command line, and one more.
MAX_FILES_PER_CONCERN = 6
#: The longest a module may be.
MAX_LINES = 1000
#: Brute-force references that only the tests use (the ``time`` rung of the model ladder,
#: which the package uses, stays in balance/core/sampled.py).
ORACLES = (
    "crank_train_newton_euler",
    "block_force_newton_euler",
    "crank_torque_newton_euler",
    "proposal_force_samples",
    "proposal_roll_samples",
)


def _modules(root: Path = PACKAGE) -> list[Path]:
    return sorted(p for p in root.rglob("*.py") if "__pycache__" not in p.parts)


@functools.cache
def identifiers(source: str) -> frozenset[str]:
    """The names in Python source: identifiers only, not strings or comments (read once per
    text: every concern's count reads the same files)."""
    tokens = tokenize.generate_tokens(io.StringIO(source).readline)
    return frozenset(t.string for t in tokens if t.type == tokenize.NAME)


class _Facts(NamedTuple):
    """What the tests below read from one module's syntax tree."""

    #: The names of the functions it defines, at any depth.
    functions: frozenset[str]
    #: Its imports of balance's modules under another name: "``module.name`` as ``alias``".
    renamed_imports: tuple[str, ...]
    #: ``(line, name)`` of each public function (in ``__all__``) that has parameters and no
    #: numpydoc Parameters section.
    undocumented: tuple[tuple[int, str], ...]


@functools.cache
def _facts(source: str) -> _Facts:
    """One module's facts, from one parse of its source (kept small: the syntax trees of the
    whole package are some 300 000 objects, which every later full garbage collection of
    the test process would walk)."""
    tree = ast.parse(source)
    functions, renamed = set(), []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            functions.add(node.name)
        elif isinstance(node, ast.Import):
            renamed += [
                f"{a.name} as {a.asname}"
                for a in node.names
                if a.name.startswith("balance") and a.asname
            ]
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("balance"):
            renamed += [
                f"{node.module}.{a.name} as {a.asname}"
                for a in node.names
                if a.asname and a.asname != a.name
            ]
    public: list[str] = []
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            assert isinstance(node.value, ast.List | ast.Tuple)
            public = [e.value for e in node.value.elts if isinstance(e, ast.Constant)]
    undocumented = []
    for node in tree.body:
        if not isinstance(node, ast.FunctionDef) or node.name not in public:
            continue
        args = node.args
        takes = [a for a in args.posonlyargs + args.args + args.kwonlyargs]
        if not (takes or args.vararg or args.kwarg):
            continue
        doc = ast.get_docstring(node) or ""
        if not re.search(r"^\s*Parameters\n\s*-{10}", doc, re.M):
            undocumented.append((node.lineno, node.name))
    return _Facts(frozenset(functions), tuple(renamed), tuple(undocumented))


def files_naming(concern: str, root: Path = PACKAGE) -> list[str]:
    """The modules under ``root`` with an identifier that contains ``concern``."""
    return [
        str(p.relative_to(root.parent))
        for p in _modules(root)
        if any(concern in name.lower() for name in identifiers(p.read_text(encoding="utf-8")))
    ]


@pytest.mark.parametrize("concern", CONCERNS)
def test_each_concern_lives_in_a_few_files(concern):
    files = files_naming(concern)
    assert len(files) <= MAX_FILES_PER_CONCERN, f"{concern}: {len(files)} files: {files}"


def test_the_count_reads_identifiers_not_text(tmp_path):
    """The count above could pass by reading nothing: it counts a name, not a comment or a
    string, and it finds the bearing loads' own module."""
    root = tmp_path / "balance"
    root.mkdir()
    (root / "named.py").write_text("def bearing_loads():\n    return 1\n")
    (root / "mentioned.py").write_text('# bearing\nTEXT = "bearing mount"\n')
    assert files_naming("bearing", root) == ["balance/named.py"]
    assert "balance/core/bearings.py" in files_naming("bearing")


def test_no_module_is_too_long():
    long = {
        str(p.relative_to(PACKAGE.parent)): n
        for p in _modules()
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES
    }
    assert not long, long


def test_oracles_live_in_the_tests():
    defined_in_package = {
        name
        for p in _modules()
        for name in _facts(p.read_text(encoding="utf-8")).functions
        if name in ORACLES
    }
    assert not defined_in_package
    # a definition in the tests, found by its `def` line (the tests are not parsed: they
    # are four times the package's source)
    in_tests = {
        name
        for p in _modules(TESTS)
        for name in re.findall(
            r"^[ \t]*def[ \t]+(\w+)[ \t]*\(", p.read_text(encoding="utf-8"), re.M
        )
    }
    assert set(ORACLES) <= in_tests, set(ORACLES) - in_tests


def test_the_package_cites_its_own_docs():
    """Users of the package have its docs (docs/conventions.md, docs/layout-format.md …),
    not the project's contract file."""
    citing = [
        str(p.relative_to(PACKAGE.parent))
        for p in _modules()
        if re.search(r"CONTRACT", p.read_text(encoding="utf-8"))
    ]
    assert not citing, citing


def test_no_module_of_the_package_is_imported_under_another_name():
    renamed = [
        f"{p.name}: {text}"
        for p in _modules()
        for text in _facts(p.read_text(encoding="utf-8")).renamed_imports
    ]
    assert not renamed, renamed


def _public_functions_without_parameters() -> list[str]:
    return [
        f"{p.relative_to(PACKAGE.parent)}:{line} {name}"
        for p in _modules()
        for line, name in _facts(p.read_text(encoding="utf-8")).undocumented
    ]


def test_every_public_function_documents_its_parameters():
    """numpydoc: a public function (in its module's ``__all__``) with parameters has a
    Parameters section."""
    missing = _public_functions_without_parameters()
    assert not missing, f"{len(missing)} without a Parameters section: {missing}"
