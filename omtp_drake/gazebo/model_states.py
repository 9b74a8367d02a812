"""Gazebo's model and link states: ``/gazebo/model_states`` (``gazebo_msgs/ModelStates``) and
``/gazebo/link_states`` (``LinkStates``): every model in the world (its frame's pose and
twist) and every link of them (``model::link``), in the world frame, the twists' linear and
angular velocities of the origin expressed in the world, as both branches fill them.

When, by branch (a transport names its own):

- ``noetic`` (ROS 1's ``gazebo_ros_api_plugin``): one message per physics update (it
  connects to the world's update event once the topic has a subscriber): the transport
  polls the publication at every update of :class:`~omtp_drake.gazebo.world.GazeboWorld`
  while the topic is subscribed (``lazy``).
- ``ros2`` (``gazebo_ros_state``): every ``1 / update_rate`` s of simulated time, its
  default ``update_rate`` :data:`STATE_RATE_HZ`, subscribed or not. gazebo_ros_state
  names the topics ``model_states`` and ``link_states`` in the plugin's namespace; the
  course's worlds (and this cell) put it under ``/gazebo``, the names ROS 1 gives them.

The models and their order are :meth:`GazeboModels.names
<omtp_drake.gazebo.models.GazeboModels.names>`: the fixed ones, then the parts in the world.
"""

from __future__ import annotations

from typing import Literal

from omtp_drake.gazebo.messages import EntityStates, LinkStates, ModelStates
from omtp_drake.gazebo.schedule import Periodic, Publication
from omtp_drake.gazebo.world import GazeboWorld

#: gazebo_ros_state's default ``<update_rate>`` (ROS 2), Hz.
STATE_RATE_HZ = 100.0
MODEL_STATES = "/gazebo/model_states"
LINK_STATES = "/gazebo/link_states"
#: The gazebo_ros_pkgs branch whose rules a transport follows.
Branch = Literal["noetic", "ros2"]


def entity_states(world: GazeboWorld, t: float, links: bool) -> EntityStates:
    """The world's models (``links``: their links) at ``t``: names, ``X_WE``, twists in world."""
    models = world.models
    entities = models.links() if links else models.models()
    poses, twists = [], []
    for _, body in entities:
        X, v, w = models.relative(body, None)
        poses.append(X)
        twists.append((*map(float, v), *map(float, w)))
    kind = LinkStates if links else ModelStates
    return kind(t, tuple(name for name, _ in entities), tuple(poses), tuple(twists))


def state_publications(world: GazeboWorld, branch: Branch) -> list[Publication]:
    """``/gazebo/model_states`` and ``/gazebo/link_states`` of ``world`` as ``branch`` publishes
    them (see the module doc)."""
    period = world.update_period if branch == "noetic" else 1.0 / STATE_RATE_HZ
    plugin = "gazebo_ros_api_plugin" if branch == "noetic" else "gazebo_ros_state"

    def publication(topic: str, kind: type, links: bool) -> Publication:
        def make(t: float) -> EntityStates:
            return entity_states(world, t, links)

        return Publication(topic, kind, Periodic(period, make), lazy=branch == "noetic", plugin=plugin)

    return [publication(MODEL_STATES, ModelStates, False), publication(LINK_STATES, LinkStates, True)]
