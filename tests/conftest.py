"""Shared fixtures: stations are built once per session (building costs ~0.5 s)."""

import logging

import pytest

from omtp_drake.cell.station import build_station

logging.getLogger("drake").setLevel(logging.ERROR)


@pytest.fixture(scope="session")
def factory():
    """The lecture 6 world (both arms, cameras, conveyor, no parts).

    Shared: never add its diagram to another builder (build your own station).
    """
    return build_station("omtp_factory")

