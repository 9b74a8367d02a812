"""Shared fixtures (stations are built once per session: building costs ~0.5 s) and
the Hypothesis profiles.

Property tests are derandomized by default: every run, on every machine, draws the
same examples, so the README's test command gives everyone the same result and no
example found elsewhere is replayed from a local database. Exploring new examples
is an opt-in: ``OMTP_HYPOTHESIS=explore pytest ...`` (``bench/bench_fuzz.py`` does
that with many more examples); a failure it finds is kept as an ``@example``.
"""

import logging
import os

import pytest
from hypothesis import settings

from omtp_drake.cell.station import build_station
from omtp_drake.errors import UnknownNameError
from omtp_drake.scenario import load_scenario

settings.register_profile("repeatable", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
_PROFILES = ("repeatable", "explore")
_profile = os.environ.get("OMTP_HYPOTHESIS", "repeatable")
if _profile not in _PROFILES:
    raise UnknownNameError("OMTP_HYPOTHESIS profile", _profile, _PROFILES)
settings.load_profile(_profile)

logging.getLogger("drake").setLevel(logging.ERROR)


@pytest.fixture(scope="session")
def factory():
    """The lecture 6 world (both arms, cameras, conveyor, no parts).

    Shared: never add its diagram to another builder (build your own station).
    """
    return build_station(load_scenario("omtp_factory"))
