"""Every Gazebo plugin of a loaded cell, as both transports serve them: what the
scenario's models carry in their ``<gazebo>`` tags (a robot file, a student's world,
a launch file's spawns) and the cell's own equivalents (the arms' joint states, the
logical cameras' RGB-D views).

:func:`gazebo_plugins` reads the plugins once; a transport turns each
:class:`~omtp_drake.gazebo.schedule.Publication` into a publisher and each
:class:`~omtp_drake.gazebo.schedule.Subscription` into a subscriber of its own
middleware, and logs :attr:`GazeboPlugins.warnings` once (one line per plugin the cell
does not simulate, as Gazebo would load it and this cell cannot).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from omtp_drake.gazebo.camera import camera_publications, camera_views
from omtp_drake.gazebo.conveyor import conveyor_services
from omtp_drake.gazebo.joint_pose_trajectory import trajectory_plugins
from omtp_drake.gazebo.joint_states import arm_joint_states, joint_state_publisher
from omtp_drake.gazebo.proximity_ray import beam_publications
from omtp_drake.gazebo.schedule import Publication, Subscription
from omtp_drake.gazebo.services import PluginService
from omtp_drake.gazebo.vacuum_gripper import gripper_publications, gripper_services

if TYPE_CHECKING:
    from omtp_drake.scenario import Scenario
    from omtp_drake.script import Cell


@dataclass
class GazeboPlugins:
    """The publications, subscriptions and services of a cell's plugins."""

    publications: list[Publication] = field(default_factory=list)
    subscriptions: list[Subscription] = field(default_factory=list)
    services: list[PluginService] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def gazebo_plugins(cell: Cell) -> GazeboPlugins:
    """The plugins of ``cell`` (see the module doc); a model's plugin with a bad setting is
    one ConfigError naming it."""
    out = GazeboPlugins(publications=arm_joint_states(cell))
    for model in cell.scenario.models:
        for publisher in model.gazebo.joint_state_publishers:
            out.publications.append(joint_state_publisher(cell, model.name, publisher))
    for view in camera_views(cell):
        out.publications += camera_publications(cell, view)
    out.subscriptions = [plugin.subscription() for plugin in trajectory_plugins(cell)]
    out.publications += gripper_publications(cell) + beam_publications(cell)
    out.services += gripper_services(cell) + conveyor_services(cell)
    out.warnings = unknown_plugins(cell.scenario)
    return out


def unknown_plugins(scenario: Scenario) -> list[str]:
    """One line per plugin of the models that the cell does not run."""
    lines = []
    for model in scenario.models:
        for plugin in model.gazebo.unknown_plugins:
            where = f" on sensor link {plugin.link!r}" if plugin.link else ""
            lines.append(
                f"{model.file}: plugin {plugin.name!r} ({plugin.filename}){where} is not simulated; ignored"
            )
    return lines
