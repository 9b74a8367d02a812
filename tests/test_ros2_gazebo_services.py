"""Gazebo's model services on ROS 2 with real ``gazebo_msgs`` type support, built here from
the definitions in omtp_drake/ros2/interfaces (no gazebo_msgs wheel exists): a student's plain
rclpy client in another process (tests/ros2_scripts/gazebo_services_node.py, nothing of ours
imported, gazebo_msgs on its PYTHONPATH) spawns a course box under ``omtp-drake ros2
lecture7_conveyor``, reads its state, moves it and deletes it, over Fast DDS on loopback in a
domain of its own. Without a compiler the cell says once why the services are off.
"""

from __future__ import annotations

import json
import logging
import os
import shutil

import pytest
from test_ros2 import SCRIPTS, domain, needs_ros2, run_cell_with_node

from omtp_drake.ros2 import interface_build

__all__ = ["domain"]  # the fixture, used by name

needs_compiler = pytest.mark.skipif(
    shutil.which("cc") is None or shutil.which("c++") is None,
    reason="no C/C++ compiler to build gazebo_msgs: apt-get install g++",
)


@pytest.fixture(scope="module")
def interfaces():
    """The built packages' folder (built once into the model cache, as the cell builds it)."""
    return interface_build.interfaces_path()


@needs_ros2
@needs_compiler
def test_a_students_rclpy_client_spawns_moves_and_deletes_a_box(tmp_path, domain, interfaces, monkeypatch):
    monkeypatch.setenv(
        "PYTHONPATH", os.pathsep.join(p for p in (str(interfaces), os.environ.get("PYTHONPATH")) if p)
    )
    out = tmp_path / "seen.json"
    _, cell_err = run_cell_with_node(
        ["lecture7_conveyor"], [str(SCRIPTS / "gazebo_services_node.py"), str(domain), str(out)], domain
    )
    seen = json.loads(out.read_text())
    from omtp_drake.ros2 import gazebo_services

    assert seen["spawn"] == [True, "SpawnModel: Successfully spawned entity"]
    # Any other model: refused with the layer's one message (what is supported).
    assert seen["spawn_other"][0] is False
    assert "this cell spawns the course's parts only" in seen["spawn_other"][1]
    # Asked at z 1.3 above the belt: there, or falling onto it (x, y as asked).
    assert seen["spawned"]["success"]
    assert seen["spawned"]["xyz"][:2] == pytest.approx([1.2, 2.5], abs=0.01)
    assert 0.9 < seen["spawned"]["xyz"][2] <= 1.3 + 1e-6
    assert seen["link"]["success"] and seen["link"]["frame_id"] == "world"
    assert seen["set"] is True
    assert seen["moved"]["xyz"][:2] == pytest.approx([1.2, 2.0], abs=0.01)
    assert 0.9 < seen["moved"]["xyz"][2] <= 1.6 + 1e-6
    assert seen["delete"] == [True, "DeleteModel: successfully deleted model"]
    assert seen["deleted"]["success"] is False
    assert seen["delete_unknown"] == [False, "DeleteModel: model does not exist"]
    # /pause_physics: /clock stands still for 1 s of wall time; /unpause_physics: it runs again.
    assert seen["paused_clock"][0] == seen["paused_clock"][1]
    assert seen["unpaused_clock"] > seen["paused_clock"][1]
    assert gazebo_services.NOT_SERVED not in cell_err
    # /reset_simulation: answered, refused in one error line (the layer's, as ROS 1's
    # NotSupportedError), and time did not go back.
    refused = [line for line in cell_err.splitlines() if "/reset_simulation" in line]
    assert len(refused) == 1, cell_err[-3000:]
    assert "(Gazebo sets simulated time back to 0) is not supported" in refused[0]
    assert "/reset_world puts the parts back" in refused[0]
    assert seen["after_reset_simulation"] >= seen["unpaused_clock"]


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
