"""Gazebo's own ROS API on the cell (``gazebo_ros``'s API plugin), under ``/gazebo``.

Topics: ``/gazebo/model_states`` (``gazebo_msgs/ModelStates``) and
``/gazebo/link_states`` (``LinkStates``), in the world frame, one message per
physics update as ``gazebo_ros`` publishes them (it connects to the world's
update event once a subscriber is there): here one per plant step
(``plant_config.time_step``), from the first subscription on.

A ``gazebo_msgs/ModelState`` published on ``/gazebo/set_model_state`` moves the
model as the service does (Gazebo subscribes to that topic too).

Services: ``get_model_state``, ``set_model_state``, ``get_link_state`` (an entity
is a model, ``model::link``, or the world: ``""``, ``world``, ``map``; an unknown
one answers ``success: False`` with Gazebo's status message), ``spawn_urdf_model``
and ``spawn_sdf_model`` (the course's part only, see :mod:`omtp_drake.ros.gazebo.spawn`),
``delete_model`` (a part), ``pause_physics``, ``unpause_physics``, ``reset_world``
(every part in the world back where it entered it, at rest; the arms stay under
their controllers) and ``reset_simulation`` (not supported: simulated time cannot
go back here).

Pause. A paused Gazebo world stops its clock: no physics update, no ``/clock``,
so a script's ``rospy.sleep`` (or any call that waits on simulated time) waits
until something unpauses it. Here nothing else can: such a call ends the run
(``ROSInterruptException``, the report's ``shutdown`` says why), as the user's
Ctrl-C ends a script that hangs in the course. Services keep answering while
paused (Gazebo's do).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from omtp_drake.errors import NotSupportedError
from omtp_drake.ros.comm.interfaces import EmptyService
from omtp_drake.ros.comm.messages import Header, Message, Time, Twist, Vector3
from omtp_drake.ros.gazebo.cell_services import Service
from omtp_drake.ros.gazebo.interfaces import (
    DeleteModel,
    GetLinkState,
    GetModelState,
    LinkState,
    LinkStates,
    ModelStates,
    SetModelState,
)
from omtp_drake.ros.gazebo.models import WORLD_NAMES, GazeboModels
from omtp_drake.ros.gazebo.sensor_topics import Source
from omtp_drake.ros.gazebo.spawn import PartSpawner, place_part
from omtp_drake.ros.tf.convert import pose_msg, rigid

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("rospy")

MODEL_STATES = "/gazebo/model_states"
LINK_STATES = "/gazebo/link_states"
SET_MODEL_STATE = "/gazebo/set_model_state"


class PushedSource(Source):
    """A topic the cell publishes by itself into the session (at physics updates, or
    latched): ``poll`` has nothing; its type is known for checks."""

    def __init__(self, msg_class: Any):
        self.msg_class = msg_class

    def poll(self) -> list[tuple[float, Any]]:
        return []


def twist_msg(v: np.ndarray, w: np.ndarray) -> Message:
    return Twist(Vector3(*map(float, v)), Vector3(*map(float, w)))


class GazeboWorld:
    """Gazebo's ROS API on ``session``'s cell (see the module doc)."""

    def __init__(self, session: Graph):
        self.session = session
        self.cell = session.cell
        self.models = GazeboModels(session.cell)
        self.paused = False
        self._stepping = False
        self._get_count: dict[str, int] = {}
        #: Called at every physics update (after the plant's step), with the time.
        self.step_hooks: list[Any] = []

    # ------------------------------------------------------------ physics updates

    @property
    def step(self) -> float:
        """The physics update period (s): the plant's time step."""
        return float(self.cell.scenario.plant_config.time_step)

    def start_stepping(self) -> None:
        """From now on the step hooks run at every physics update."""
        if not self._stepping:
            self._stepping = True
            self.cell.runtime.driver.every(self.step, self._on_step)

    def _on_step(self) -> None:
        t = self.cell.time
        for hook in list(self.step_hooks):
            hook(t)
        for topic, build in ((MODEL_STATES, self.model_states), (LINK_STATES, self.link_states)):
            if self.session.num_subscribers(topic):
                self.session.publish(topic, build(), t)

    def on_subscribe(self, topic: str) -> None:
        if topic in (MODEL_STATES, LINK_STATES):
            self.start_stepping()

    def clock_stopped(self) -> Optional[str]:
        """Why simulated time cannot advance now (None: it can)."""
        if not self.paused:
            return None
        return (
            "simulated time stands still: Gazebo's physics is paused (/gazebo/pause_physics) and "
            "nothing else in this run calls /gazebo/unpause_physics (in the course the script waits "
            "for ever)"
        )

    # ------------------------------------------------------------ topics

    def model_states(self) -> Message:
        return self._states(ModelStates(), self.models.models())

    def link_states(self) -> Message:
        return self._states(LinkStates(), self.models.links())

    def _states(self, msg: Any, entities: list[tuple[str, Any]]) -> Any:
        """``msg`` (ModelStates or LinkStates) filled with the entities' world states."""
        for name, body in entities:
            X, v, w = self.models.relative(body, None)
            msg.name.append(name)
            msg.pose.append(pose_msg(X))
            msg.twist.append(twist_msg(v, w))
        return msg

    # ------------------------------------------------------------ services

    def frame(self, name: str) -> tuple[bool, Any]:
        """(found, body or None for the world) of a reference entity."""
        if name in WORLD_NAMES:
            return True, None
        body = self.models.body(name)
        return body is not None, body

    def reference(
        self, name: str, response: Any, service: str, field: str, scoped: str = "link"
    ) -> tuple[bool, Any]:
        """:meth:`frame` of a request's reference entity ``name`` (its ``field``); when there is
        none, ``response``'s status message says so as ``service`` does in Gazebo (forgot to
        scope the ``scoped``?)."""
        found, frame = self.frame(name)
        if not found:
            response.status_message = (
                f"{service}: reference {field} not found, did you forget to scope the {scoped} by model name?"
            )
        return found, frame

    def get_model_state(self, request: Any) -> Any:
        response: Any = GetModelState._response_class()
        body = self.models.body(request.model_name) if "::" not in request.model_name else None
        if body is None:
            return self._no_model(response, "GetModelState", request.model_name)
        count = self._get_count[request.model_name] = self._get_count.get(request.model_name, 0) + 1
        response.header = Header(seq=count, stamp=Time(self.cell.time), frame_id=request.relative_entity_name)
        found, frame = self.reference(
            request.relative_entity_name, response, "GetModelState", "relative_entity_name", "body"
        )
        if not found:
            return response
        X, v, w = self.models.relative(body, frame)
        response.pose, response.twist = pose_msg(X), twist_msg(v, w)
        response.success, response.status_message = True, "GetModelState: got properties"
        return response

    def get_link_state(self, request: Any) -> Any:
        response: Any = GetLinkState._response_class()
        body = self.models.body(request.link_name) if "::" in request.link_name else None
        if body is None:
            response.status_message = (
                "GetLinkState: link not found, did you forget to scope the link by model name?"
            )
            return response
        found, frame = self.reference(request.reference_frame, response, "GetLinkState", "reference_frame")
        if not found:
            return response
        X, v, w = self.models.relative(body, frame)
        response.link_state = LinkState(
            link_name=request.link_name,
            pose=pose_msg(X),
            twist=twist_msg(v, w),
            reference_frame=request.reference_frame,
        )
        response.success, response.status_message = True, "GetLinkState: got state"
        return response

    def set_model_state(self, request: Any) -> Any:
        state = request.model_state
        response: Any = SetModelState._response_class()
        if state.model_name not in self.models.names():
            return self._no_model(
                response, "SetModelState", state.model_name, logged_as="Updating ModelState"
            )
        self._parts_only("/gazebo/set_model_state", "moves", state.model_name)
        found, frame = self.frame(state.reference_frame)
        if not found:
            response.status_message = "SetModelState: specified reference frame entity does not exist"
            return response
        X = rigid(state.pose, "model_state.pose")
        v = np.array([state.twist.linear.x, state.twist.linear.y, state.twist.linear.z], dtype=float)
        w = np.array([state.twist.angular.x, state.twist.angular.y, state.twist.angular.z], dtype=float)
        if frame is not None:
            X_WF = self.models.pose(frame)
            X, v, w = X_WF @ X, X_WF.rotation() @ v, X_WF.rotation() @ w
        place_part(self.cell, self.models.part_of[state.model_name], X, v, w)
        response.success, response.status_message = True, "SetModelState: set model state done"
        return response

    @staticmethod
    def _no_model(response: Any, service: str, model: str, logged_as: str = "") -> Any:
        """``response`` for a ``model`` the world does not have: Gazebo's error line (as
        ``logged_as``, else ``service``) and status message."""
        _log.error("%s: model [%s] does not exist", logged_as or service, model)
        response.status_message = f"{service}: model does not exist"
        return response

    def _parts_only(self, service: str, verb: str, model: str) -> None:
        """One error for a model that is not a part (the arms are welded and servoed here)."""
        if model not in self.models.parts:
            in_world = sorted(self.models.parts & set(self.models.names()))
            raise NotSupportedError(
                f"{service} of {model!r}: here it {verb} parts only; the parts in the world: "
                f"{', '.join(in_world) or 'none'}"
            )

    def delete_model(self, request: Any) -> Any:
        response: Any = DeleteModel._response_class()
        if request.model_name not in self.models.names():
            return self._no_model(response, "DeleteModel", request.model_name)
        self._parts_only("/gazebo/delete_model", "deletes", request.model_name)
        part = self.models.part_of[request.model_name]
        self.cell.remove_part(part)
        if part != request.model_name:
            self.models.rename_part(part, part)  # spawned again, it is itself
        response.success, response.status_message = True, "DeleteModel: successfully deleted model"
        return response

    def pause(self, on: bool) -> Any:
        self.paused = on
        _log.info("gazebo: physics %s at t = %.3f s", "paused" if on else "running", self.cell.time)
        return EmptyService._response_class()

    def reset_simulation(self, _request: Any) -> Any:
        raise NotSupportedError(
            "/gazebo/reset_simulation (Gazebo sets simulated time back to 0) is not supported: "
            "simulated time cannot go back here; /gazebo/reset_world puts the parts back without the clock"
        )

    def services(self) -> list[Service]:
        spawner = PartSpawner(self.cell, self.models, self.reference)
        return [
            Service("/gazebo/get_model_state", GetModelState, self.get_model_state),
            Service("/gazebo/set_model_state", SetModelState, self.set_model_state),
            Service("/gazebo/get_link_state", GetLinkState, self.get_link_state),
            *spawner.services(),
            Service("/gazebo/delete_model", DeleteModel, self.delete_model),
            Service("/gazebo/pause_physics", EmptyService, lambda _r: self.pause(True)),
            Service("/gazebo/unpause_physics", EmptyService, lambda _r: self.pause(False)),
            Service("/gazebo/reset_world", EmptyService, spawner.reset_world),
            Service("/gazebo/reset_simulation", EmptyService, self.reset_simulation),
        ]

    def sources(self) -> dict[str, Source]:
        return {MODEL_STATES: PushedSource(ModelStates), LINK_STATES: PushedSource(LinkStates)}
