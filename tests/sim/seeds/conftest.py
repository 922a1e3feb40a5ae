"""Every seed test starts with no World, an empty stage and no SimulationApp."""

from __future__ import annotations

import pytest

from manip.sim import World, create_new_stage
from manip.sim.core.app import get_app


def _fresh() -> None:
    app = get_app()
    if app is not None:
        app.close()
    World.clear_instance()
    create_new_stage()


@pytest.fixture(autouse=True)
def fresh_world():
    _fresh()
    yield
    _fresh()
