"""Gazebo's model services (gazebo_ros's API plugin, ROS 1's names): what a request gets.

``get_model_state``, ``set_model_state``, ``get_link_state`` (an entity is a model,
``model::link``, or the world: ``""``, ``world``, ``map``; an unknown one answers
``success: False`` with Gazebo's status message and error line), ``delete_model`` (a
part), the spawn services and ``reset_world`` (:mod:`omtp_drake.gazebo.spawn`);
``reset_simulation`` is refused (:meth:`WorldServices.reset_simulation`). Moving or
deleting a model that is no part is one NotSupportedError (the arms are welded and
servoed here). Poses and twists are in the reference entity's frame, the velocity
differences expressed in that frame, as Gazebo computes them.

A transport turns its request message into a call here and the reply into its response;
ROS 2 has none of these types on PyPI (``gazebo_msgs``), see docs/ros2.md.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.errors import NotSupportedError
from omtp_drake.gazebo.models import WORLD_NAMES
from omtp_drake.gazebo.spawn import PartSpawner, Reply, place_part, reference_missing

if TYPE_CHECKING:
    from omtp_drake.gazebo.world import GazeboWorld

_log = logging.getLogger("gazebo")


@dataclass(frozen=True)
class EntityState(Reply):
    """``get_model_state`` / ``get_link_state``'s reply: the entity's pose ``X_FE`` and twist
    (vx, vy, vz, wx, wy, wz) in the reference frame; ``seq``: get_model_state's header count
    of that model's calls."""

    X: RigidTransform = field(default_factory=RigidTransform)
    twist: tuple[float, ...] = (0.0,) * 6
    seq: int = 0


class WorldServices:
    """The services above on ``world``."""

    def __init__(self, world: GazeboWorld):
        self.world = world
        self.models = world.models
        self._get_count: dict[str, int] = {}
        self.spawner = PartSpawner(world.cell, world.models, self.reference)

    def reset_simulation(self, name: str, reset_world: str) -> NoReturn:
        """gazebo_ros's ``reset_simulation`` (``World::Reset``: simulated time back to 0, the world
        as loaded, ``/clock`` jumping back), served as ``name``: one NotSupportedError pointing at
        ``reset_world`` (the transport's name of it). Refused, not done by halves: the cell's
        state is not the Drake Context alone (the plugins' schedules, the spawner's and the
        ledger's counts, the controllers' goals, the tf buffer, a script's pending sleeps), and
        nothing yet puts all of it back at t = 0."""
        raise NotSupportedError(
            f"{name} (Gazebo sets simulated time back to 0) is not supported: "
            f"simulated time cannot go back here; {reset_world} puts the parts back without the clock"
        )

    def reference(self, name: str) -> Any:
        """The body of reference entity ``name`` (None: the world); KeyError when none."""
        if name in WORLD_NAMES:
            return None
        body = self.models.body(name)
        if body is None:
            raise KeyError(name)
        return body

    def _state(self, body: Any, frame: Any, message: str, seq: int = 0) -> EntityState:
        X, v, w = self.models.relative(body, frame)
        return EntityState(True, message, X, (*map(float, v), *map(float, w)), seq)

    def get_model_state(self, model: str, relative_entity: str) -> EntityState:
        body = self.models.body(model) if "::" not in model else None
        if body is None:
            return EntityState(False, _no_model("GetModelState", model))
        seq = self._get_count[model] = self._get_count.get(model, 0) + 1
        try:
            frame = self.reference(relative_entity)
        except KeyError:
            return EntityState(
                False, reference_missing("GetModelState", "relative_entity_name", "body"), seq=seq
            )
        return self._state(body, frame, "GetModelState: got properties", seq)

    def get_link_state(self, link: str, reference_frame: str) -> EntityState:
        body = self.models.body(link) if "::" in link else None
        if body is None:
            return EntityState(
                False, "GetLinkState: link not found, did you forget to scope the link by model name?"
            )
        try:
            frame = self.reference(reference_frame)
        except KeyError:
            return EntityState(False, reference_missing("GetLinkState", "reference_frame"))
        return self._state(body, frame, "GetLinkState: got state")

    def set_model_state(
        self,
        model: str,
        X_FM: Callable[[], RigidTransform],
        v: np.ndarray,
        w: np.ndarray,
        reference_frame: str,
    ) -> Reply:
        """Model ``model`` to pose ``X_FM()`` (read once the request is otherwise valid: a
        transport's conversion may refuse it) with twist (``v``, ``w``) in ``reference_frame``."""
        if model not in self.models.names():
            return Reply(False, _no_model("SetModelState", model, logged_as="Updating ModelState"))
        self._parts_only("/gazebo/set_model_state", "moves", model)
        try:
            frame = self.reference(reference_frame)
        except KeyError:
            return Reply(False, "SetModelState: specified reference frame entity does not exist")
        X, v, w = X_FM(), np.asarray(v, dtype=float), np.asarray(w, dtype=float)
        if frame is not None:
            X_WF = self.models.pose(frame)
            X, v, w = X_WF @ X, X_WF.rotation() @ v, X_WF.rotation() @ w
        place_part(self.world.cell, self.models.part_of[model], X, v, w)
        return Reply(True, "SetModelState: set model state done")

    def delete_model(self, model: str) -> Reply:
        if model not in self.models.names():
            return Reply(False, _no_model("DeleteModel", model))
        self._parts_only("/gazebo/delete_model", "deletes", model)
        part = self.models.part_of[model]
        self.world.cell.remove_part(part)
        if part != model:
            self.models.rename_part(part, part)  # spawned again, it is itself
        return Reply(True, "DeleteModel: successfully deleted model")

    def _parts_only(self, service: str, verb: str, model: str) -> None:
        """One error for a model that is not a part."""
        if model not in self.models.parts:
            in_world = sorted(self.models.parts & set(self.models.names()))
            raise NotSupportedError(
                f"{service} of {model!r}: here it {verb} parts only; the parts in the world: "
                f"{', '.join(in_world) or 'none'}"
            )


def _no_model(service: str, model: str, logged_as: str = "") -> str:
    """Gazebo's error line for a ``model`` the world does not have (as ``logged_as``, else
    ``service``), and its status message."""
    _log.error("%s: model [%s] does not exist", logged_as or service, model)
    return f"{service}: model does not exist"
