"""Gazebo's model services on ROS 2 with real ``gazebo_msgs`` type support, built here from
the definitions in omtp_drake/ros2/interfaces (no gazebo_msgs wheel exists). A student's plain
rclpy client in another process (tests/ros2_scripts/gazebo_services_node.py, nothing of ours
imported, gazebo_msgs on its PYTHONPATH) spawning, moving and deleting a course box under
``omtp-drake ros2 lecture7_conveyor`` is tests/test_ros2_gazebo_world.py's
(``test_a_students_rclpy_client_spawns_moves_and_deletes_a_box``: it shares that module's cell
with the spawner's peer). Here: without a compiler the cell says once why the services are off.
"""

from __future__ import annotations

import logging

import pytest
from test_ros2 import needs_ros2

from omtp_drake.ros2 import interface_build


@needs_ros2
def test_without_a_compiler_the_services_are_off_with_one_warning(tmp_path, monkeypatch, caplog):
    from omtp_drake.ros2 import gazebo_services

    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))  # nothing built there
    monkeypatch.setenv("PATH", str(tmp_path))  # no cc, no c++
    with pytest.raises(interface_build.InterfacesUnavailable, match=r"no cc or c\+\+ compiler on PATH"):
        interface_build.interfaces_path()
    with caplog.at_level(logging.WARNING, logger="gazebo"):
        served = gazebo_services.serve_gazebo_services(node=None, api=None, run_on_cell=None)  # type: ignore[arg-type]
    assert served is False
    (line,) = [r.getMessage() for r in caplog.records]
    assert line.startswith(gazebo_services.NOT_SERVED) and "apt-get install gcc g++" in line
    assert not (tmp_path / "cache").exists() or not list((tmp_path / "cache").rglob("COMPLETE"))
