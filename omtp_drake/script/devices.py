"""The scripted cell's vacuum grippers and logical cameras (the course's services), and waiting."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.poses import PoseStamped
from omtp_drake.cell.suction import GripperState
from omtp_drake.errors import SimulationError, check_duration
from omtp_drake.sim.runtime import FactoryRuntime


def wait_until(
    runtime: FactoryRuntime,
    condition: Callable[[], bool],
    timeout: float,
    *,
    period: float = 0.05,
    what: str = "the condition",
) -> None:
    """Runs the cell until ``condition()`` is true (checked every ``period`` s);
    raises SimulationError after ``timeout`` s."""
    timeout = check_duration("timeout", timeout)
    period = check_duration("period", period)
    end = runtime.time + timeout
    while not condition():
        if runtime.time >= end - 1e-9:
            raise SimulationError(
                f"t={runtime.time:.2f} s: waited {timeout:g} s for {what}; it did not happen"
            )
        runtime.advance_to(min(end, runtime.time + period))


class Gripper:
    """A vacuum gripper (the course's ``/gripperN/control`` service). Get it from
    :meth:`~omtp_drake.script.cell.Cell.gripper`."""

    def __init__(self, runtime: FactoryRuntime, robot: str):
        self._runtime = runtime
        self.robot = robot

    def on(self) -> None:
        """Vacuum on: a part touching the cup is attached on the second check (the first at
        once, the next 0.1 s later), as the course's gripper plugin."""
        self._runtime.enable_gripper(self.robot)

    def off(self) -> None:
        """Vacuum off: a held part is released at the next plant step and falls."""
        self._runtime.disable_gripper(self.robot)

    def state(self) -> GripperState:
        return self._runtime.gripper_state(self.robot)

    @property
    def attached(self) -> bool:
        """A part is held."""
        return self.state().attached

    @property
    def part(self) -> str:
        """The held part's name ("" when none)."""
        return self.state().part

    def wait_for_attach(self, timeout: float = 1.0) -> str:
        """Waits until a part is attached; returns its name (SimulationError after ``timeout`` s)."""
        wait_until(self._runtime, lambda: self.attached, timeout, what=f"{self.robot}'s gripper to attach")
        return self.part


class Camera:
    """A logical camera. Get it from :meth:`~omtp_drake.script.cell.Cell.camera`."""

    def __init__(self, runtime: FactoryRuntime, name: str):
        self._runtime = runtime
        self.name = name

    def image(self) -> LogicalCameraImage:
        """The latest image, stamped with the time it was taken."""
        return self._runtime.camera_image(self.name)

    def color_image(self) -> np.ndarray:
        """What the camera's RGB-D view shows now, as a (height, width, 4) RGBA uint8 array
        (for ``imshow``). Raises ``ConfigError`` for a camera without ``rgbd: true``."""
        from omtp_drake.cell.rgbd import color_image, rgba_array

        return rgba_array(color_image(self._runtime.station.diagram, self._runtime.context, self.name))

    def parts(self, type: str = "object") -> dict[str, PoseStamped]:
        """Name -> pose (in this camera's frame, at the image's time) of every model of
        ``type`` the latest image reports."""
        image = self.image()
        return {m.name: image.pose_of(m.name) for m in image.models if m.type == type and m.name}
