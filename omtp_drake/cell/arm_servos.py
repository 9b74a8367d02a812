"""The arms in the station: each at its initial pose, held by its position servo
(:func:`omtp_drake.cell.arms.add_arm_controller`), with its ports exported as
``<robot>.position`` (in), ``<robot>.position_measured``, ``<robot>.velocity_estimated``,
``<robot>.state_estimated`` and ``<robot>.torque_commanded`` (out)."""

from __future__ import annotations

from collections.abc import Mapping

from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import Demultiplexer

from omtp_drake.cell import arms
from omtp_drake.cell.cell_models import ArmHandles


def add_arm_servos(
    builder: DiagramBuilder, plant: MultibodyPlant, handles: Mapping[str, ArmHandles], gravity: list[float]
) -> None:
    """Each arm of ``handles`` at its initial pose (the plant's default positions; the plant
    is finalized) and held by its servo."""
    for arm in handles.values():
        plant.SetDefaultPositions(arm.arm, arms.named_pose(arm.config.initial_pose, arm.config))
    for arm in handles.values():
        _add_arm_servo(builder, plant, arm, gravity)


def _add_arm_servo(
    builder: DiagramBuilder, plant: MultibodyPlant, handles: ArmHandles, gravity: list[float]
) -> None:
    """The arm's position servo and its exported ports."""
    name = handles.config.name
    sampler, controller, handles.control_plant = arms.add_arm_controller(
        builder, plant, handles.arm, handles.config, gravity, payloads=handles.payloads
    )
    handles.sampler = sampler
    handles.controller = controller
    sampler.connect_input(builder, f"{name}.position")
    state = plant.get_state_output_port(handles.arm)
    n = plant.num_positions(handles.arm)
    demux = builder.AddNamedSystem(f"{name}.demux", Demultiplexer([n, n]))
    builder.Connect(state, demux.get_input_port())
    builder.ExportOutput(demux.get_output_port(0), f"{name}.position_measured")
    builder.ExportOutput(demux.get_output_port(1), f"{name}.velocity_estimated")
    builder.ExportOutput(state, f"{name}.state_estimated")
    builder.ExportOutput(controller.GetOutputPort("actuation"), f"{name}.torque_commanded")
