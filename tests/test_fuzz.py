"""Bad input never crashes: a corpus of malformed files and hypothesis fuzzing.

Every case must end with exit code 0 (a valid layout, contract JSON on stdout) or 2 (one
line on stderr per problem, each naming the file, nothing on stdout), never a traceback or
exit 1.

The number of fuzz cases follows the hypothesis profile: ``ci`` and ``default`` run a few
hundred; ``HYPOTHESIS_PROFILE=fuzz python -m pytest tests/test_fuzz.py`` runs the long
campaign recorded in the docs.
"""

from __future__ import annotations

import copy
import json
import os
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from balance.cli import app

runner = CliRunner()
BAD = Path(__file__).parent / "data" / "bad"
NO_COMMENT = {"latin1.yaml": "is not UTF-8", "binary.yaml": "binary (it contains NUL bytes)"}
FUZZ_EXAMPLES = int(os.environ.get("BALANCE_FUZZ_EXAMPLES", "150"))


def _expected(path: Path) -> str:
    if path.name in NO_COMMENT:
        return NO_COMMENT[path.name]
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("# expect: "), path
    return first.removeprefix("# expect: ")


def _check(path: Path, args: tuple[str, ...] = ("analyse",)) -> tuple[int, str]:
    result = runner.invoke(app, [*args, str(path), "-f", "json"])
    assert result.exit_code in (0, 2), (result.exit_code, result.stderr, result.exception)
    if result.exit_code == 2:
        assert result.stdout == ""
        lines = result.stderr.splitlines()
        assert lines and result.stderr.endswith("\n"), result.stderr
        assert all(line.startswith(f"balance: {path}") for line in lines), result.stderr
        assert len(set(lines)) == len(lines), result.stderr  # each problem once
        assert "Traceback" not in result.stderr
    else:
        assert json.loads(result.stdout)["schema"] == "balance.analysis/1"
    return result.exit_code, result.stderr


@pytest.mark.parametrize("path", sorted(BAD.glob("*.yaml")), ids=lambda p: p.name)
@pytest.mark.parametrize("command", ["analyse", "propose"])
def test_bad_corpus(path, command, monkeypatch):
    from balance.io import yamlsource

    converted = [0]
    convert = yamlsource._convert

    def counting(*args: Any) -> Any:
        converted[0] += 1
        return convert(*args)

    monkeypatch.setattr(yamlsource, "_convert", counting)
    code, message = _check(path, (command,))
    assert code == 2
    assert _expected(path) in message
    # refused without expanding: the values read stay within the budget, where the
    # billion laughs would expand to 9**10 of them (work counted, not timed)
    assert converted[0] <= yamlsource.MAX_NODES + 1


def test_layout_expand_on_the_corpus():
    for path in sorted(BAD.glob("*.yaml")):
        result = runner.invoke(app, ["layout", "expand", str(path)])
        assert result.exit_code == 2, path
        assert result.stderr.startswith(f"balance: {path}") and "Traceback" not in result.stderr


# --- generated layouts, then broken ------------------------------------------------------

_angles = st.sampled_from([0, 90, 180, "270 deg", "-45 deg", "1.5 rad", 360, 720])


@st.composite
def valid_layouts(draw: Any) -> dict[str, Any]:
    n = draw(st.integers(1, 6))
    data: dict[str, Any] = {
        "name": draw(st.text(min_size=1, max_size=20).filter(lambda s: s.strip())),
        "speed": draw(st.sampled_from(["6000 rpm", "100 Hz", "500 rad/s", "3000rpm", "7000 RPM"])),
        "geometry": {
            "stroke": draw(st.sampled_from(["86 mm", "0.07 m", "2.5 in"])),
            "conrod_length": draw(st.sampled_from(["143 mm", "0.2 m", "7 in"])),
        },
        "masses": draw(
            st.sampled_from(
                [
                    {"reciprocating": "0.6 kg", "rotating": "0.4 kg"},
                    {
                        "piston_group": "0.4 kg",
                        "conrod": "0.5 kg",
                        "conrod_cg_to_big_end": "40 mm",
                        "conrod_inertia": "1.5e-3 kg m^2",
                        "crank_unbalance": "0.2 kg",
                    },
                ]
            )
        ),
    }
    if draw(st.booleans()):
        data["crank"] = {
            "throws": draw(st.lists(_angles, min_size=1, max_size=n)),
            "spacing": "90 mm",
        }
        if draw(st.booleans()):
            data["crank"]["banks"] = ["-45 deg", "45 deg"]
    else:
        data["cylinders"] = [
            {"throw": draw(_angles), "bank": draw(_angles), "z": f"{90 * i} mm"} for i in range(n)
        ]
    return data


def _paths(node: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [prefix] if prefix else []
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _paths(value, (*prefix, i))
    return out


def _get_parent(data: Any, path: tuple[Any, ...]) -> Any:
    for part in path[:-1]:
        data = data[part]
    return data


_garbage = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**30), 10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=30),
    st.sampled_from(
        [
            "86 kg",
            "nan mm",
            "inf",
            "1e308 m",
            "-0",
            "0 mm",
            "5 furlongs",
            "1/s",
            "m**99999",
            "°",
            "%",
            "1e-320 kg",
            "NaN",
            "0x1F",
            "1_000 mm",
            "∞",
        ]
    ),
    st.lists(st.integers(), max_size=3),
    st.dictionaries(st.text(max_size=5), st.integers(), max_size=2),
)


@st.composite
def broken_layouts(draw: Any) -> str:
    data = draw(valid_layouts())
    paths = _paths(data)
    action = draw(st.sampled_from(["drop", "retype", "rename", "extreme", "duplicate", "none"]))
    data = copy.deepcopy(data)
    if action in ("drop", "retype", "rename", "extreme") and paths:
        path = draw(st.sampled_from(paths))
        parent = _get_parent(data, path)
        key = path[-1]
        if action == "drop":
            del parent[key]
        elif action == "retype":
            parent[key] = draw(_garbage)
        elif action == "rename" and isinstance(parent, dict):
            parent[draw(st.text(min_size=1, max_size=12))] = parent.pop(key)
        elif action == "extreme":
            parent[key] = draw(st.sampled_from([1e308, -1e308, 1e-308, 0, -1, 1e300]))
    text = yaml.safe_dump(data, allow_unicode=True, sort_keys=False)
    if action == "duplicate":
        lines = text.splitlines()
        i = draw(st.integers(0, len(lines) - 1))
        lines.insert(i, lines[i])
        text = "\n".join(lines) + "\n"
    return text


@settings(
    max_examples=FUZZ_EXAMPLES,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(text=broken_layouts())
def test_fuzzed_layouts_end_in_0_or_2(tmp_path, text):
    path = tmp_path / "fuzz.yaml"
    path.write_text(text, encoding="utf-8")
    _check(path)


@pytest.mark.parametrize("key", ["<", "<tag>", "<<<"])
def test_a_key_that_looks_like_a_union_tag_is_an_unknown_key(tmp_path, key):
    """The fuzzer renamed a key to '<' (a union member's location tag begins with '<'): the
    error's location lost the key and the reader failed with an internal error."""
    path = tmp_path / "odd.yaml"
    layout = "name: odd\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
    layout += "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\n"
    layout += f"cylinders: [{{throw: 0, bank: 0, z: 0 mm}}]\n'{key}': '0'\n"
    path.write_text(layout, encoding="utf-8")
    result = runner.invoke(app, ["analyse", str(path)])
    assert result.exit_code == 2, result.output
    assert f"odd.yaml:6:1: {key}: unknown key '{key}'" in result.output


@settings(
    max_examples=FUZZ_EXAMPLES // 3, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(raw=st.binary(max_size=300))
def test_fuzzed_bytes_end_in_0_or_2(tmp_path, raw):
    path = tmp_path / "bytes.yaml"
    path.write_bytes(raw)
    _check(path)
