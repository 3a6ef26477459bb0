"""Shared test fixtures and hypothesis profiles."""

from __future__ import annotations

import os

import numpy as np
import pytest
import typer.testing
from hypothesis import settings

settings.register_profile("default", max_examples=60, deadline=None)
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("long", max_examples=2000, deadline=None)
settings.load_profile(
    os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "default")
)


def _built_once(build):
    """typer's CliRunner builds the click command of the whole application (every command,
    its options and their type adapters: about 30 ms) on every invoke, and the tests invoke
    the same application hundreds of times; build it once per application (and again if
    commands are added).  Click commands are made to be invoked many times."""
    built = {}

    def get(app):
        key = (id(app), len(app.registered_commands), len(app.registered_groups))
        if key not in built:
            built[key] = (app, build(app))  # holding the app keeps its id unique
        return built[key][1]

    return get


typer.testing._get_command = _built_once(typer.testing._get_command)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)
