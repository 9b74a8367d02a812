"""The course's part spawner under ros-run, wired as the scenario's launch file wires it.

With ``spawner.start_service`` set (the scenario's launch file remaps the
spawner node's ``/start_spawn`` to it, e.g. ``/spawn_object_at_robot2``), the
spawner is the course's ``conveyor_spawner_node``:

- ``start_service`` starts a periodic timer: the first part one ``spawner.period``
  after the call, then one every period (at the spawner's pose and seeded
  variance), until ``/stop_spawn``. A start while the timer runs changes nothing
  (a roscpp Timer's ``start``). Each spawn publishes the latched
  ``/spawned_part`` (``std_msgs/Header``: ``seq`` the spawner's count,
  ``stamp`` the time, ``frame_id`` the drawn object's name in the spawner's config).
  With the plugin's ``objects`` (:mod:`omtp_drake.scenario.conveyor_spawner`), a tick's
  callback spawns after its drawn ``spawn_timing_variance``, and the next tick's
  callback starts no earlier than that (one spinner thread).
- ``spawner.stop_node``: the course's ``spawn_object_once.py`` runs too: at every
  ``/gazebo/model_states`` message (every physics update) it calls ``/stop_spawn``
  while a model named like "object" is in the world. A start while a part is in
  the world is stopped before it fires.

Without it, ros-run's own services: ``/spawn_object_once`` or
``/spawn_object_at_robot2`` (by the robot nearest the spawn point) spawn a part
at once, and ``/start_spawn`` / ``/stop_spawn`` switch the scenario's automatic
spawner; a spawn refused by its one-part-at-a-time rule spawns nothing.

Either way a call that spawns nothing answers normally (the course's
services raise nothing) and logs one warning; the run's report lists it
(``empty_spawn_calls``).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from omtp_drake.errors import OmtpError, SimulationError
from omtp_drake.ros.comm._core import callback_start, draw, kind_of, spawn
from omtp_drake.ros.comm.interfaces import EmptyService
from omtp_drake.ros.comm.messages import Header, Time
from omtp_drake.ros.gazebo.cell_services import Service, ServiceFailure

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import SpawnerConfig
    from omtp_drake.ros.gazebo.graph import Graph
    from omtp_drake.ros.gazebo.ros_api import GazeboWorld

_log = logging.getLogger("rospy")

SPAWNED_PART = "/spawned_part"
#: The object's name in the course's spawner configs (``objects: - name: box``).
OBJECT_NAME = "box"
_EPS = 1e-9


def empty_response() -> Any:
    return EmptyService._response_class()


class CourseSpawner:
    """The course's spawner node (and its stop node) on ``world``'s cell."""

    def __init__(self, session: Graph, world: GazeboWorld, config: SpawnerConfig):
        self.session, self.world, self.cell = session, world, session.cell
        self.config = config
        self.running = False
        self.count = 0
        self._next = 0.0
        #: When the running tick's callback spawns (None: no callback running) and when
        #: the last one returned (the plugin's single-threaded spinner).
        self._due: float | None = None
        self._returned = -math.inf
        self._fired = False
        self._started_by = ""
        world.step_hooks.append(self._on_step)

    def start(self, name: str) -> Any:
        if self.running:
            self._nothing(name, "the spawner runs already: a start changes nothing (its timer is started)")
            return empty_response()
        self.running, self._fired, self._started_by = True, False, name
        self._next = self.cell.time + self.config.period
        self.world.start_stepping()
        return empty_response()

    def stop(self, _request: Any) -> Any:
        self.running = False
        return empty_response()

    def _nothing(self, name: str, why: str) -> None:
        text = f"t={self.cell.time:.3f} {name}: nothing spawned: {why}"
        _log.warning("%s", text)
        self.session.empty_spawn_calls.append(text)

    def _on_step(self, t: float) -> None:
        if self._due is not None:
            # A callback waiting its spawn_timing_variance spawns, stopped or not.
            if t >= self._due - _EPS:
                self._due, self._returned = None, t
                self._fire(t)
            return
        if not self.running:
            return
        if self.config.stop_node:
            objects = [n for n in self.world.models.names() if "object" in n]
            if objects:
                self.running = False
                if not self._fired:
                    self._nothing(
                        self._started_by,
                        f"{objects[0]} is in the world, so the course's spawn_object_once node stopped "
                        "the spawner (/stop_spawn) before its first spawn",
                    )
                return
        if t >= self._next - _EPS:
            start = callback_start(self._next, self._returned)
            self._next += self.config.period
            delay = self._delay()
            if delay <= _EPS:
                self._returned = t
                self._fire(t)
            else:
                self._due = start + delay

    def _delay(self) -> float:
        """The next spawn's drawn spawn_timing_variance (0 without the plugin's objects)."""
        if not self.config.objects:
            return 0.0
        cell = self.cell
        return draw(self.config, cell.scenario.seed, cell.runtime.pool.spawn_count).delay

    def _fire(self, t: float) -> None:
        self.count += 1
        pool = self.cell.runtime.pool
        kind = (
            kind_of(self.config, self.cell.scenario.seed, pool.spawn_count)
            if self.config.objects
            else OBJECT_NAME
        )
        try:
            part = spawn(self.cell.station, self.cell.runtime.context, pool)
        except OmtpError as e:
            self.count -= 1
            _log.error("conveyor_spawner: failed to spawn: %s", e)
            return
        self._fired = True
        _log.info("conveyor_spawner: spawned %s at t = %.3f s", part, t)
        header = Header(seq=self.count, stamp=Time(t), frame_id=kind)
        self.session.latched[SPAWNED_PART] = (t, -1, header)
        self.session.publish(SPAWNED_PART, header, t)

    def services(self) -> list[Service]:
        name = self.config.start_service
        return [
            Service(name, EmptyService, lambda _r: self.start(name)),
            Service("/stop_spawn", EmptyService, self.stop),
        ]


def _at_once_services(session: Graph, spawner: SpawnerConfig) -> list[Service]:
    """ros-run's own spawn services (see the module doc)."""
    cell = session.cell
    robots = {r.name: np.asarray(r.xy, dtype=float) for r in cell.scenario.robots}
    xy = np.asarray(spawner.xyz[:2], dtype=float)
    nearest = min(robots, key=lambda name: float(np.linalg.norm(robots[name] - xy))) if robots else ""
    name = {"robot1": "/spawn_object_once", "robot2": "/spawn_object_at_robot2"}.get(nearest)

    def spawn_now(_request: Any) -> Any:
        try:
            part = cell.spawn_part()
        except SimulationError as e:
            text = f"t={cell.time:.3f} {name}: nothing spawned: {e}"
            _log.warning("%s", text)
            session.empty_spawn_calls.append(text)
            return empty_response()
        except OmtpError as e:
            raise ServiceFailure(str(e)) from None
        _log.info("spawned %s", part)
        return empty_response()

    def switch(on: bool) -> Callable[[Any], Any]:
        def handler(_request: Any) -> Any:
            cell.runtime.auto_spawn = on
            return empty_response()

        return handler

    services = [
        Service("/start_spawn", EmptyService, switch(True)),
        Service("/stop_spawn", EmptyService, switch(False)),
    ]
    if name is not None:
        services.append(Service(name, EmptyService, spawn_now))
    return services


def spawner_services(session: Graph, world: GazeboWorld) -> list[Service]:
    """The spawner's services of ``session``'s scenario (none without a spawner)."""
    config = session.cell.scenario.spawner
    if config is None:
        return []
    if not config.start_service:
        return _at_once_services(session, config)
    return CourseSpawner(session, world, config).services()
