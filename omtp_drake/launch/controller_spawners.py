"""``controller_manager``'s spawners in a launch file: which controllers start on which robot.

ROS 1: a ``<rosparam file="controllers.yaml" command="load" [ns=...]/>`` puts each
controller's parameters under ``/<ns>/<controller>``; ``<node pkg="controller_manager"
type="spawner" args="NAME ... [--namespace NS] [--stopped]">`` loads the named
controllers from there through the controller manager of its namespace (the node's
``ns``, or ``--namespace``; ``--stopped``: loaded, not started) and starts them. The
controller manager is the ``gazebo_ros_control`` plugin of the model whose
``robotNamespace`` is that namespace.

:func:`start_spawned_controllers` gives each such model its started controllers
(:class:`~omtp_drake.scenario.ros_control.RosControlConfig`); a spawner whose namespace
has no such model, or whose controller has no parameters, is a WorkspaceError naming the
launch file's line, as the spawner fails there.
"""

from __future__ import annotations

import dataclasses
import shlex
from collections.abc import Sequence

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.roslaunch import Launch, Node, get_param, join_name
from omtp_drake.scenario import ModelConfig
from omtp_drake.scenario.ros_control import RosControlConfig
from omtp_drake.scenario.ros_control_parse import spawned_only, with_controller_params

SPAWNERS = (("controller_manager", "spawner"),)
#: The spawner's options that take a value (their values are no controller names).
_VALUED = ("--namespace", "--timeout", "--shutdown-timeout")


def spawner_request(node: Node) -> tuple[str, list[str]]:
    """(the controller manager's namespace, the controllers it starts) of a spawner node."""
    words = shlex.split(node.args)
    namespace, names, stopped = node.namespace, [], False
    k = 0
    while k < len(words):
        word = words[k]
        if word.startswith("--namespace="):
            namespace = word.split("=", 1)[1]
        elif word in _VALUED:
            namespace = words[k + 1] if word == "--namespace" and k + 1 < len(words) else namespace
            k += 1
        elif word == "--stopped":
            stopped = True
        elif not word.startswith("-"):
            names.append(word)
        k += 1
    return "/" + namespace.strip("/"), [] if stopped else names


def start_spawned_controllers(
    models: Sequence[ModelConfig], launch: Launch, *, cell_namespaces: Sequence[str] = ()
) -> list[ModelConfig]:
    """``models`` with the controllers the launch's spawners start (see the module doc). A
    spawner in one of ``cell_namespaces`` starts the controllers of a course piece the cell
    drives itself (the UR arms'): it is left to the cell."""
    cell = {"/" + n.strip("/") for n in cell_namespaces}
    out = list(models)
    for node in launch.nodes:
        if (node.pkg, node.type) not in SPAWNERS:
            continue
        namespace, names = spawner_request(node)
        if namespace in cell:
            continue
        owners = [
            k
            for k, m in enumerate(out)
            if m.gazebo.ros_control is not None
            and m.gazebo.ros_control.plugin == "gazebo_ros_control"
            and "/" + _setup(m).namespace.strip("/") == namespace
        ]
        if not owners:
            raise WorkspaceError(
                f"{node.where}: spawner: no controller manager in namespace {namespace!r} (no spawned model "
                "has a gazebo_ros_control plugin with that robotNamespace)"
            )
        document = {}
        for name in names:
            try:
                document[name] = get_param(launch.params, join_name(namespace, name))
            except KeyError:
                raise WorkspaceError(
                    f"{node.where}: spawner: controller {name!r} has no parameters under "
                    f"{join_name(namespace, name)} (load its YAML with <rosparam> first)"
                ) from None
        model = out[owners[0]]
        config = with_controller_params(_setup(model), document, node.where, names)
        out[owners[0]] = dataclasses.replace(
            model, gazebo=dataclasses.replace(model.gazebo, ros_control=config)
        )
    return out


def _setup(model: ModelConfig) -> RosControlConfig:
    config = model.gazebo.ros_control
    if config is None:
        raise WorkspaceError(f"{model.file}: the model has no gazebo_ros_control plugin")
    return config


def activate_ros2_controllers(
    models: Sequence[ModelConfig], names: Sequence[str], where: str
) -> tuple[list[ModelConfig], list[str]]:
    """ROS 2: ``models`` with the controllers a launch's ``controller_manager`` spawners name
    (``names``, in order) active on the ``gazebo_ros2_control`` plugin that declares them, and
    the warning lines: a name no plugin declares (its spawner fails: "controller not found",
    and the launch goes on) and, without any spawner, nothing changes (the YAML's controllers
    in order, as before)."""
    out: list[ModelConfig] = list(models)
    warnings: list[str] = []
    if not names:
        return out, warnings
    found: set[str] = set()
    for k, model in enumerate(out):
        config = model.gazebo.ros_control
        if config is None or config.plugin != "gazebo_ros2_control":
            continue
        mine = [n for n in names if n in {c.name for c in config.declared}]
        found |= set(mine)
        active = spawned_only(config, mine, f"{where} ({model.name})", refuse_conflicts=False)
        out[k] = dataclasses.replace(model, gazebo=dataclasses.replace(model.gazebo, ros_control=active))
    for name in names:
        if name not in found:
            warnings.append(
                f"{where}: spawner: controller {name!r} is declared by no gazebo_ros2_control plugin"
            )
    return out, warnings
