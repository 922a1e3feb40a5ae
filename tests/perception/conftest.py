"""Every perception test starts with no World and an empty stage (`fresh_world`, tests/conftest.py)."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _every_test_in_a_fresh_world(fresh_world):
    yield
