"""The course's conveyor spawner plugin's parameters and rules (no cell built here)."""

import math

import numpy as np
import pytest
import yaml

from omtp_drake.errors import ConfigError
from omtp_drake.launch.nodes import with_robot_namespace
from omtp_drake.scenario import SpawnerConfig
from omtp_drake.scenario.conveyor_spawner import (
    SpawnObjectConfig,
    callback_start,
    draw,
    object_pose,
    pool_kinds,
    spawner_params,
)

# A group's conveyor_objects.yaml, as they wrote it.
GROUP_YAML = """
spawner:
  reference_frame: world
  spawn_period: 4.0
  randomization_seed: 7
  objects:
    - name: box
      mesh_resource: package://omtp_gazebo/meshes/conveyor_objects/box.stl
      initial_pose:
        position: [1.2, 3.0, 1.0]
        orientation: [0.0, 0.0, 0.0]
      lateral_placement_variance: 0.2
      yaw_placement_variance: 45.0
      spawn_timing_variance: 0.5
    - name: flat_box
      mesh_resource: package://group_parts/meshes/flat_box.stl
      initial_pose:
        position: [1.2, 3.0, 1.0]
        orientation: [0.0, 0.0, 1.5707963]
      lateral_placement_variance: 0.1
      yaw_placement_variance: 10.0
      spawn_timing_variance: 1.0
"""


def _config(text=GROUP_YAML):
    return yaml.safe_load(text)["spawner"]


def _spawner(**changes):
    params = spawner_params(_config(), "conveyor_objects.yaml")
    params.update(changes)
    params["objects"] = [SpawnObjectConfig(**o) for o in params["objects"]]
    return SpawnerConfig(**params)


def test_the_plugins_parameters_are_read_as_it_reads_them():
    params = spawner_params(_config(), "conveyor_objects.yaml")
    assert (params["period"], params["randomization_seed"], params["reference_frame"]) == (4.0, 7, "world")
    box, flat = params["objects"]
    assert box["xyz"] == [1.2, 3.0, 1.0] and flat["rpy"][2] == pytest.approx(math.pi / 2)
    # yaw in degrees in the file, radians in the config; the others as given
    assert box["yaw_variance"] == pytest.approx(math.radians(45.0))
    assert (box["lateral_variance"], flat["timing_variance"]) == (0.2, 1.0)


@pytest.mark.parametrize(
    "edit, message",
    [
        (("spawn_period: 4.0", "spawn_period: 4"), "spawn_period 4 must be a double"),
        (
            ("lateral_placement_variance: 0.2", "lateral_placement_variance: 0"),
            "lateral_placement_variance 0",
        ),
        (("randomization_seed: 7", "randomization_seed: 7.5"), "randomization_seed 7.5 must be an integer"),
        (("      spawn_timing_variance: 0.5\n", ""), "needs 'spawn_timing_variance'"),
        (("position: [1.2, 3.0, 1.0]", "position: [1, 3.0, 1.0]"), "1 must be a double"),
    ],
)
def test_what_the_plugins_loader_refuses_is_one_line(edit, message):
    with pytest.raises(ConfigError, match="conveyor_objects.yaml") as e:
        spawner_params(_config(GROUP_YAML.replace(*edit, 1)), "conveyor_objects.yaml")
    assert message in str(e.value)


def test_same_seeds_same_spawns_other_seeds_other_spawns():
    spawner = _spawner()
    first = [draw(spawner, 3, k) for k in range(20)]
    assert first == [draw(spawner, 3, k) for k in range(20)]
    assert first != [draw(spawner, 4, k) for k in range(20)]
    reseeded = _spawner(randomization_seed=8)
    assert first != [draw(reseeded, 3, k) for k in range(20)]
    assert {d.kind for d in first} == {0, 1}


def test_an_object_with_no_variance_spawns_where_its_config_puts_it_at_each_tick():
    spawner = SpawnerConfig(objects=[SpawnObjectConfig(name="box", xyz=[1.2, 1.8, 1.0])])
    for k in range(5):
        d = draw(spawner, 3, k)
        assert (d.kind, d.lateral, d.yaw, d.delay) == (0, 0.0, 0.0, 0.0)
        np.testing.assert_allclose(object_pose(spawner, d).translation(), [1.2, 1.8, 1.0])


def test_each_draw_is_within_its_objects_ranges_and_moves_along_y():
    spawner = _spawner()
    for k in range(200):
        d = draw(spawner, 0, k)
        obj = spawner.objects[d.kind]
        assert abs(d.lateral) <= obj.lateral_variance and abs(d.yaw) <= obj.yaw_variance
        assert 0.0 <= d.delay <= obj.timing_variance
        X = object_pose(spawner, d)
        # the plugin adds the lateral draw to y, turns about the object's own z
        np.testing.assert_allclose(X.translation(), np.add(obj.xyz, [0.0, d.lateral, 0.0]))
        yaw = math.atan2(X.rotation().matrix()[1, 0], X.rotation().matrix()[0, 0])
        assert math.remainder(yaw - obj.rpy[2] - d.yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


def test_pool_parts_are_built_as_the_objects_their_spawns_draw():
    spawner = _spawner()
    pool = [f"object_{k}" for k in range(1, 9)]
    kinds = pool_kinds(spawner, 5, pool)
    assert [kinds[n] for n in pool] == [spawner.objects[draw(spawner, 5, j).kind].name for j in range(8)]
    assert pool_kinds(SpawnerConfig(), 5, pool) == {}


def test_a_late_callback_starts_when_the_previous_one_returned():
    assert callback_start(4.0, 3.5) == 4.0
    assert callback_start(4.0, 4.8) == 4.8


def test_spawn_models_robot_namespace_goes_into_plugins_without_one():
    urdf = (
        '<robot name="r"><link name="a"/><gazebo><plugin name="p" filename="x.so"/>'
        '<plugin name="q" filename="y.so"><robotNamespace>/own</robotNamespace></plugin></gazebo></robot>'
    )
    text = with_robot_namespace(urdf, "/robot2")
    assert (
        "<robotNamespace>/robot2</robotNamespace>" in text and "<robotNamespace>/own</robotNamespace>" in text
    )
    assert with_robot_namespace(urdf, "/") == urdf


def test_spawn_models_reference_frame_places_a_model_relative_to_a_link(tmp_path):
    """spawn_model -reference_frame MODEL::LINK (a model spawned before it): the pose is in
    that link's frame; a frame nobody spawned: Gazebo's failed spawn, one warning line."""
    import shutil
    from pathlib import Path

    from omtp_drake.launch import own_cell

    src = tmp_path / "src"
    shutil.copytree(Path(__file__).resolve().parent / "fixtures" / "catkin_ws" / "src", src)
    launch = src / "omtp_gazebo" / "launch" / "spawn_static_world_objects.launch"
    launch.write_text(
        launch.read_text().replace(
            "</launch>",
            """  <param name="bin_2_description"
         command="$(find xacro)/xacro '$(find omtp_support)/urdf/bin/bin.xacro' prefix:=bin_2_"/>
  <node name="bin_2_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-reference_frame robot1_pedestal::robot1_pedestal_link -x -0.6 -y 0.7 -urdf -model bin_2_
              -param bin_2_description"/>
  <node name="bin_3_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-reference_frame nowhere -urdf -model bin_3_ -param bin_2_description"/>
</launch>""",
        )
    )
    cell = own_cell("omtp_lecture6 lecture6_assignment1.launch", workspace=[src], environ={})
    bins = {b.name: b.xyz for b in cell.scenario.bins}
    np.testing.assert_allclose(bins["bin_2"], [-0.1, 2.5, 0.0], atol=1e-9)
    assert "bin_3" not in bins
    assert any("-reference_frame 'nowhere'" in w and "not spawned" in w for w in cell.warnings)
