"""Joint states: ``gazebo_ros_joint_state_publisher`` on any model, and the cell's arms.

- A model's ``libgazebo_ros_joint_state_publisher.so``: ``<ns>/joint_states`` with its
  ``<joint_name>``\\ s' positions and velocities, every ``1 / update_rate`` s of
  simulated time (the plugin's default rate, 100 Hz, is the scenario's), stamped with
  the simulated time of the update, ``frame_id`` empty. A joint the model lacks is one
  ConfigError when the plugins are read (the plugin refuses to load).
- The arms: ``/joint_states`` (every arm, as the course's launch file merges them) and
  ``/robotN/joint_states`` (one arm), by the URDF's joint names
  (``robot1_shoulder_pan_joint``...), at :data:`JOINT_STATE_RATE_HZ`, the course's
  controllers' state rate; positions only, as their joint_state_controller sends them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from omtp_drake.cell.arms import JOINT_NAMES
from omtp_drake.errors import ConfigError
from omtp_drake.gazebo.messages import JointStates
from omtp_drake.gazebo.schedule import Periodic, Publication, topic

if TYPE_CHECKING:
    from omtp_drake.scenario.gazebo_tags import JointStatePublisherPlugin
    from omtp_drake.script import Cell

#: The course's joint trajectory controllers publish their state at 50 Hz.
JOINT_STATE_RATE_HZ = 50.0
#: The topic of the merged joint states (both transports).
JOINT_STATES = "/joint_states"


def arm_joint_states(cell: Cell) -> list[Publication]:
    """``/joint_states`` (every arm) and ``/robotN/joint_states`` of the cell's arms."""
    arms = list(cell.station.arms)

    def make(robots: list[str]) -> Periodic[JointStates]:
        names = tuple(f"{robot}_{joint}" for robot in robots for joint in JOINT_NAMES)

        def message(t: float) -> JointStates:
            positions = [float(q) for robot in robots for q in cell.arm(robot).joint_values()]
            return JointStates(t, names, tuple(positions))

        return Periodic(1.0 / JOINT_STATE_RATE_HZ, message)

    out = [Publication(f"/{robot}/joint_states", JointStates, make([robot]), plugin=robot) for robot in arms]
    if arms:
        out.append(Publication(JOINT_STATES, JointStates, make(arms), plugin="arms"))
    return out


def joint_state_publisher(cell: Cell, model: str, plugin: JointStatePublisherPlugin) -> Publication:
    """The ``joint_states`` of ``plugin`` on ``model`` (see the module doc)."""
    station = cell.station
    plant = station.plant
    instance = station.models[model]
    known = [plant.get_joint(j).name() for j in plant.GetJointIndices(instance)]
    missing = [j for j in plugin.joint_names if j not in known]
    if missing:
        raise ConfigError(
            f"joint state publisher {plugin.name!r} of {model!r}: joint {missing[0]!r} does not exist; "
            f"valid: {', '.join(known)}"
        )
    joints = [plant.GetJointByName(j, instance) for j in plugin.joint_names]
    names = tuple(j.name() for j in joints)

    def message(t: float) -> JointStates:
        context = plant.GetMyContextFromRoot(cell.runtime.context)
        return JointStates(
            t,
            names,
            tuple(float(j.GetOnePosition(context)) for j in joints),
            tuple(float(j.GetOneVelocity(context)) for j in joints),
        )

    return Publication(
        topic(plugin.namespace, "joint_states"),
        JointStates,
        Periodic(1.0 / plugin.update_rate, message),
        plugin=plugin.name,
    )
