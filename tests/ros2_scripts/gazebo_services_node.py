"""A student's rclpy client of Gazebo's model services (gazebo_ros's ROS 2 names and types):
spawns a box as the course's spawner writes it, reads its state, moves it, deletes it,
asks for a model that does not exist, then pauses and unpauses the physics, watching /clock,
and asks for /reset_simulation.
Writes what it got as JSON to argv[2].

Run as ``python gazebo_services_node.py DOMAIN OUT`` with gazebo_msgs on PYTHONPATH."""

import json
import sys
import time

import rclpy
from gazebo_msgs.msg import EntityState
from gazebo_msgs.srv import DeleteEntity, GetEntityState, SetEntityState, SpawnEntity
from geometry_msgs.msg import Pose
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

BOX = """<?xml version="1.0"?>
<robot name="box">
  <link name="box_base_link">
    <visual><geometry><mesh filename="package://omtp_gazebo/meshes/conveyor_objects/box.stl"/></geometry></visual>
    <collision><geometry><mesh filename="package://omtp_gazebo/meshes/conveyor_objects/box.stl"/></geometry></collision>
  </link>
</robot>"""


def call(node, client, request):
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=60.0)
    if future.result() is None:
        raise SystemExit(f"no reply from {client.srv_name}")
    return future.result()


def spin_for(node, seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)


def state(node, get, name, frame=""):
    reply = call(node, get, GetEntityState.Request(name=name, reference_frame=frame))
    p = reply.state.pose.position
    return {"success": reply.success, "xyz": [p.x, p.y, p.z], "frame_id": reply.header.frame_id}


def main():
    out = sys.argv[2]
    rclpy.init()
    node = rclpy.create_node("gazebo_services_client")
    spawn = node.create_client(SpawnEntity, "/spawn_entity")
    delete = node.create_client(DeleteEntity, "/delete_entity")
    get = node.create_client(GetEntityState, "/get_entity_state")
    set_state = node.create_client(SetEntityState, "/set_entity_state")
    for client in (spawn, delete, get, set_state):
        if not client.wait_for_service(timeout_sec=120.0):
            raise SystemExit(f"{client.srv_name} never came")
    seen = {}
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = 1.2, 2.5, 1.3
    reply = call(node, spawn, SpawnEntity.Request(name="my_box", xml=BOX, initial_pose=pose))
    seen["spawn"] = [reply.success, reply.status_message]
    other = (
        '<robot name="crate"><link name="l"><visual><geometry><box size="1 1 1"/></geometry>'
        "</visual></link></robot>"
    )
    reply = call(node, spawn, SpawnEntity.Request(name="crate", xml=other, initial_pose=pose))
    seen["spawn_other"] = [reply.success, reply.status_message]
    seen["spawned"] = state(node, get, "my_box")
    seen["link"] = state(node, get, "my_box::box_base_link", "world")
    moved = Pose()
    moved.position.x, moved.position.y, moved.position.z = 1.2, 2.0, 1.6
    reply = call(node, set_state, SetEntityState.Request(state=EntityState(name="my_box", pose=moved)))
    seen["set"] = reply.success
    seen["moved"] = state(node, get, "my_box")
    reply = call(node, delete, DeleteEntity.Request(name="my_box"))
    seen["delete"] = [reply.success, reply.status_message]
    seen["deleted"] = state(node, get, "my_box")
    reply = call(node, delete, DeleteEntity.Request(name="no_such_model"))
    seen["delete_unknown"] = [reply.success, reply.status_message]
    clock = []
    on_clock = lambda m: clock.append(m.clock.sec + m.clock.nanosec * 1e-9)  # noqa: E731
    node.create_subscription(Clock, "/clock", on_clock, 10)
    pause = node.create_client(Empty, "/pause_physics")
    unpause = node.create_client(Empty, "/unpause_physics")
    call(node, pause, Empty.Request())
    spin_for(node, 0.5)  # what was sent before the pause arrives
    before = clock[-1]
    spin_for(node, 1.0)
    seen["paused_clock"] = [before, clock[-1]]
    call(node, unpause, Empty.Request())
    spin_for(node, 1.0)
    seen["unpaused_clock"] = clock[-1]
    # Gazebo's /reset_simulation sets time back to 0: here it is refused (a reply all the same).
    call(node, node.create_client(Empty, "/reset_simulation"), Empty.Request())
    spin_for(node, 0.5)
    seen["after_reset_simulation"] = min(clock[clock.index(seen["unpaused_clock"]) :])
    with open(out, "w") as f:
        json.dump(seen, f)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
