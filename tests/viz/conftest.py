"""Fixtures of the viewer tests: a free TCP port per viewer."""

from __future__ import annotations

import socket

import pytest


def free_port() -> int:
    """A TCP port nothing listens on now (the OS picks it)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def port() -> int:
    return free_port()
