"""MoveIt's ``move_group`` node on a run, as the course's ``move_group.launch`` starts it:
its config (the SRDF and joint limits, :func:`omtp_drake.ros.moveit.config.install`)
and the services its capabilities advertise, when the cell has arms:

- ``/compute_ik`` (``moveit_msgs/GetPositionIK``): :mod:`omtp_drake.ros.moveit.ik_service`
- ``/compute_fk`` (``moveit_msgs/GetPositionFK``): :mod:`omtp_drake.ros.moveit.fk_service`
- ``/compute_cartesian_path`` (``moveit_msgs/GetCartesianPath``):
  :mod:`omtp_drake.ros.moveit.cartesian_service`

(The ``/move_group`` action's client is :mod:`omtp_drake.ros.moveit.move_group`.)
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Optional

from omtp_drake.ros.gazebo.cell_services import Service
from omtp_drake.ros.moveit.cartesian_service import compute_cartesian_path
from omtp_drake.ros.moveit.config import install
from omtp_drake.ros.moveit.fk_service import compute_fk
from omtp_drake.ros.moveit.ik_service import compute_ik
from omtp_drake.ros.moveit.interfaces import GetCartesianPath, GetPositionFK, GetPositionIK

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session
    from omtp_drake.ros.moveit.srdf import SemanticModel


def start_move_group(
    session: Session, srdf: Optional[str | Path] = None, package: Optional[str | Path] = None
) -> SemanticModel:
    """Installs the run's MoveIt config (``--srdf``, ``--moveit-config``; see
    :func:`~omtp_drake.ros.moveit.config.install`) and advertises move_group's services."""
    semantic = install(session, srdf, package)
    cell = session.cell
    if cell.station.arms:
        services = [
            Service("/compute_ik", GetPositionIK, lambda request: compute_ik(cell, request)),
            Service("/compute_fk", GetPositionFK, lambda request: compute_fk(cell, request)),
            Service("/compute_cartesian_path", GetCartesianPath, compute_cartesian_path),
        ]
        session.services.update({s.name: s for s in services})
    return semantic
