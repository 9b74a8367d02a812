#!/usr/bin/env python
# Spawn the course's box part with Gazebo's spawn service, as the conveyor spawner does.
import json
import sys

import rospy
from gazebo_msgs.msg import ModelStates
from gazebo_msgs.srv import SpawnModel
from geometry_msgs.msg import Pose

BOX_URDF = """<?xml version="1.0" ?>
<robot name="box" xmlns:xacro="https://www.ros.org/wiki/xacro">
  <link name="box_base_link">
    <visual>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <geometry>
        <mesh filename="package://omtp_gazebo/meshes/conveyor_objects/box.stl"/>
      </geometry>
      <material name="medium_gray"><color rgba="0.5 0.5 0.5 1.0"/></material>
    </visual>
    <collision>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <geometry>
        <mesh filename="package://omtp_gazebo/meshes/conveyor_objects/box.stl"/>
      </geometry>
    </collision>
    <inertial>
      <mass value="0.2"/>
      <inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/>
      <origin xyz="0 0 0" rpy="0 0 0"/>
    </inertial>
  </link>
</robot>
"""

SPHERE_SDF = """<sdf version="1.6"><model name="ball"><link name="link"><collision name="c">
<geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link></model></sdf>"""

rospy.init_node("spawn_part")
rospy.wait_for_service("/gazebo/spawn_urdf_model")
spawn_urdf = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel)
spawn_sdf = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)

pose = Pose()
pose.position.x = 1.2
pose.position.y = 1.8
pose.position.z = 1.1
pose.orientation.w = 1.0
resp = spawn_urdf("object_7", BOX_URDF, "omtp", pose, "world")
again = spawn_urdf("object_7", BOX_URDF, "omtp", pose, "world")
rospy.sleep(1.0)
models = rospy.wait_for_message("/gazebo/model_states", ModelStates).name
with open(sys.argv[1], "w") as f:
    json.dump(
        {
            "first": [resp.success, resp.status_message],
            "again": [again.success, again.status_message],
            "models": list(models),
        },
        f,
    )
if len(sys.argv) > 2:
    spawn_sdf("ball", SPHERE_SDF, "", pose, "world")
