"""The course's part spawner, wired as the scenario's launch file wires it: its services
(``std_srvs/Empty`` on both transports: the course's own type, which ROS 2's std_srvs has
too) and its ``/spawned_part`` topic. Its parameters and the rules of one spawn are
:mod:`omtp_drake.scenario.conveyor_spawner`'s.

With ``spawner.start_service`` set (the scenario's launch file remaps the spawner node's
``/start_spawn`` to it, e.g. ``/spawn_object_at_robot2``), the spawner is the course's
``conveyor_spawner_node`` (:class:`CourseSpawner`):

- ``start_service`` starts a periodic timer: the first part one ``spawner.period`` after
  the call, then one every period (at the spawner's pose and seeded variance), until
  ``/stop_spawn``. A start while the timer runs changes nothing (a roscpp Timer's
  ``start``). Each spawn publishes the latched ``/spawned_part`` (``std_msgs/Header``:
  ``seq`` the spawner's count, ``stamp`` the time, ``frame_id`` the drawn object's name in
  the spawner's config). With the plugin's ``objects``, a tick's callback spawns after its
  drawn ``spawn_timing_variance``, and the next tick's callback starts no earlier than
  that (one spinner thread). The timer runs in physics updates
  (:class:`~omtp_drake.gazebo.world.GazeboWorld`).
- ``spawner.stop_node``: the course's ``spawn_object_once.py`` runs too: at every
  ``/gazebo/model_states`` message (every physics update) it calls ``/stop_spawn`` while a
  model named like "object" is in the world. A start while a part is in the world is
  stopped before it fires.

Without it, the cell's own services (:func:`at_once_services`): ``/spawn_object_once`` or
``/spawn_object_at_robot2`` (by the robot nearest the spawn point) spawn a part at once,
and ``/start_spawn`` / ``/stop_spawn`` switch the scenario's automatic spawner; a spawn
refused by its one-part-at-a-time rule spawns nothing.

Either way a call that spawns nothing answers normally (the course's services raise
nothing) and logs one warning, kept in ``empty_calls`` (ros-run's report lists them).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from omtp_drake.errors import OmtpError, SimulationError
from omtp_drake.gazebo.messages import SpawnedPart
from omtp_drake.gazebo.schedule import EPS, Publication
from omtp_drake.scenario.conveyor_spawner import callback_start, draw, kind_of
from omtp_drake.sim.driver import spawn

if TYPE_CHECKING:
    from omtp_drake.gazebo.world import GazeboWorld
    from omtp_drake.scenario import SpawnerConfig

_log = logging.getLogger("gazebo")

SPAWNED_PART = "/spawned_part"
STOP_SPAWN = "/stop_spawn"
#: The object's name in the course's spawner configs (``objects: - name: box``).
OBJECT_NAME = "box"


@dataclass(frozen=True)
class EmptyService:
    """A ``std_srvs/Empty`` service of the spawner: its name and what a call does. A call
    that fails raises OmtpError (a transport answers it as its middleware's failure)."""

    name: str
    call: Callable[[], None]


class CourseSpawner:
    """The course's spawner node (and its stop node) on ``world``'s cell; calls that spawn
    nothing go into ``empty_calls``."""

    def __init__(self, world: GazeboWorld, config: SpawnerConfig, empty_calls: list[str]):
        self.world, self.cell, self.config = world, world.cell, config
        self.empty_calls = empty_calls
        self.running = False
        self.count = 0
        self._next = 0.0
        #: When the running tick's callback spawns (None: no callback running) and when
        #: the last one returned (the plugin's single-threaded spinner).
        self._due: float | None = None
        self._returned = -math.inf
        self._fired = False
        self._started_by = ""
        #: What ``/spawned_part`` has not sent yet.
        self._spawned: list[SpawnedPart] = []
        world.update_hooks.append(self._on_update)

    def start(self, name: str) -> None:
        if self.running:
            self._nothing(name, "the spawner runs already: a start changes nothing (its timer is started)")
            return
        self.running, self._fired, self._started_by = True, False, name
        self._next = self.cell.time + self.config.period
        self.world.start_updates()

    def stop(self) -> None:
        self.running = False

    def _nothing(self, name: str, why: str) -> None:
        text = f"t={self.cell.time:.3f} {name}: nothing spawned: {why}"
        _log.warning("%s", text)
        self.empty_calls.append(text)

    def _on_update(self, t: float) -> None:
        if self._due is not None:
            # A callback waiting its spawn_timing_variance spawns, stopped or not.
            if t >= self._due - EPS:
                self._due, self._returned = None, t
                self._fire(t)
            return
        if not self.running:
            return
        if self.config.stop_node and self._stopped_by_node():
            return
        if t >= self._next - EPS:
            start = callback_start(self._next, self._returned)
            self._next += self.config.period
            delay = self._delay()
            if delay <= EPS:
                self._returned = t
                self._fire(t)
            else:
                self._due = start + delay

    def _stopped_by_node(self) -> bool:
        """spawn_object_once.py's rule: True (and the spawner stopped) while an object is in the world."""
        objects = [n for n in self.world.models.names() if "object" in n]
        if not objects:
            return False
        self.running = False
        if not self._fired:
            self._nothing(
                self._started_by,
                f"{objects[0]} is in the world, so the course's spawn_object_once node stopped "
                "the spawner (/stop_spawn) before its first spawn",
            )
        return True

    def _delay(self) -> float:
        """The next spawn's drawn spawn_timing_variance (0 without the plugin's objects)."""
        if not self.config.objects:
            return 0.0
        cell = self.cell
        return draw(self.config, cell.scenario.seed, cell.runtime.pool.spawn_count).delay

    def _fire(self, t: float) -> None:
        pool = self.cell.runtime.pool
        kind = (
            kind_of(self.config, self.cell.scenario.seed, pool.spawn_count)
            if self.config.objects
            else OBJECT_NAME
        )
        try:
            part = spawn(self.cell.station, self.cell.runtime.context, pool)
        except OmtpError as e:
            _log.error("conveyor_spawner: failed to spawn: %s", e)
            return
        self.count += 1
        self._fired = True
        _log.info("conveyor_spawner: spawned %s at t = %.3f s", part, t)
        self._spawned.append(SpawnedPart(t, kind, self.count))

    def _drain(self, _t: float) -> list[SpawnedPart]:
        out, self._spawned = self._spawned, []
        return out

    def publication(self) -> Publication:
        """``/spawned_part`` (latched: a transport keeps its last message for late subscribers)."""
        return Publication(SPAWNED_PART, SpawnedPart, self._drain, plugin="conveyor_spawner")

    def services(self) -> list[EmptyService]:
        name = self.config.start_service
        return [EmptyService(name, lambda: self.start(name)), EmptyService(STOP_SPAWN, self.stop)]


def at_once_services(
    world: GazeboWorld, spawner: SpawnerConfig, empty_calls: list[str]
) -> list[EmptyService]:
    """The cell's own spawn services (see the module doc)."""
    cell = world.cell
    robots = {r.name: np.asarray(r.xy, dtype=float) for r in cell.scenario.robots}
    xy = np.asarray(spawner.xyz[:2], dtype=float)
    nearest = min(robots, key=lambda name: float(np.linalg.norm(robots[name] - xy))) if robots else ""
    name = {"robot1": "/spawn_object_once", "robot2": "/spawn_object_at_robot2"}.get(nearest)

    def spawn_now() -> None:
        try:
            part = cell.spawn_part()
        except SimulationError as e:
            text = f"t={cell.time:.3f} {name}: nothing spawned: {e}"
            _log.warning("%s", text)
            empty_calls.append(text)
            return
        _log.info("spawned %s", part)

    def switch(on: bool) -> Callable[[], None]:
        def call() -> None:
            cell.runtime.auto_spawn = on

        return call

    services = [EmptyService("/start_spawn", switch(True)), EmptyService(STOP_SPAWN, switch(False))]
    if name is not None:
        services.append(EmptyService(name, spawn_now))
    return services


@dataclass
class Spawner:
    """The spawner of a cell as a transport serves it: its services and, for the course's
    node, its ``/spawned_part`` publication."""

    services: list[EmptyService]
    publication: Publication | None = None


def spawner(world: GazeboWorld, empty_calls: list[str]) -> Spawner | None:
    """The spawner of ``world``'s scenario (None without one)."""
    config = world.cell.scenario.spawner
    if config is None:
        return None
    if not config.start_service:
        return Spawner(at_once_services(world, config, empty_calls))
    course = CourseSpawner(world, config, empty_calls)
    return Spawner(course.services(), course.publication())
