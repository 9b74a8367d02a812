#!/usr/bin/env python3
"""Lecture 7: robot 1 picks each part the break beam stopped on the belt and drops it into
bin 2 - all of it inside the logical camera's callback, the main thread in rospy.spin().
Course style: rospy subscribers, MoveIt commander, tf2, the gripper, conveyor and spawner
services. As in the course's lecture 7 behaviour, the spawner (a part every 3 s after
/start_spawn) is stopped while a part waits at the beam and started again after the
pick. Shuts down after PARTS parts.

    omtp-drake ros-run examples/ros/lecture7_belt_pick.py [PARTS] --scenario lecture7_conveyor_pick
"""

import sys

import moveit_commander
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import ConveyorBeltState, LogicalCameraImage, Proximity
from omtp_gazebo.srv import ConveyorBeltControl, VacuumGripperControl
from std_srvs.srv import Empty

CUP_ABOVE_CENTRE = 0.16  # the course's value: the cup pressed onto the part's top face
SETTLE = 0.5  # s after the beam broke: the belt has stopped the part


class BeltPicker:
    def __init__(self, parts):
        self.parts = parts
        self.picked = 0
        self.beam_time = None
        self.group = moveit_commander.MoveGroupCommander("robot1")
        self.tf_buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.tf_buffer)
        rospy.wait_for_service("/gripper1/control")
        self.gripper = rospy.ServiceProxy("/gripper1/control", VacuumGripperControl)
        self.conveyor = rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)
        self.start_spawn = rospy.ServiceProxy("/start_spawn", Empty)
        self.stop_spawn = rospy.ServiceProxy("/stop_spawn", Empty)
        bin_2 = self.tf_buffer.lookup_transform(
            "world", "bin_2_base_link", rospy.Time(0), rospy.Duration(1.0)
        )
        self.over_bin = bin_2.transform.translation
        self.group.set_named_target("R1Home")
        self.group.go(wait=True)
        self.tool_down = self.group.get_current_pose().pose.orientation
        rospy.Subscriber("/break_beam_sensor_change", Proximity, self.on_beam)
        rospy.Subscriber("/omtp/logical_camera_1", LogicalCameraImage, self.on_image, queue_size=1)

    def on_beam(self, msg):
        self.beam_time = msg.header.stamp if msg.object_detected else None
        if msg.object_detected:
            self.stop_spawn()

    def move_cup(self, x, y, z):
        target = self.group.get_current_pose().pose
        target.position.x, target.position.y, target.position.z = x, y, z
        target.orientation = self.tool_down
        self.group.set_pose_target(target)
        ok = self.group.go(wait=True)
        self.group.stop()
        self.group.clear_pose_targets()
        return ok

    def on_image(self, image):
        if self.beam_time is None or rospy.Time.now() - self.beam_time < rospy.Duration(SETTLE):
            return
        models = [m for m in image.models if m.type == "object"]
        if not models:
            return
        seen = PoseStamped()
        seen.header.frame_id = "logical_camera_1_frame"
        seen.header.stamp = rospy.Time.now()
        seen.pose = models[0].pose
        p = self.tf_buffer.transform(seen, "world", rospy.Duration(1.0)).pose.position
        self.move_cup(p.x, p.y, p.z + 0.4)
        self.gripper(True)
        self.move_cup(p.x, p.y, p.z + CUP_ABOVE_CENTRE)
        rospy.sleep(0.3)  # suction attaches on contact
        self.move_cup(p.x, p.y, p.z + 0.5)
        self.move_cup(self.over_bin.x, self.over_bin.y, self.over_bin.z + 0.8)
        self.gripper(False)
        rospy.sleep(0.5)
        self.picked += 1
        rospy.loginfo("picked %d of %d", self.picked, self.parts)
        self.beam_time = None
        if self.picked >= self.parts:
            rospy.signal_shutdown("all parts picked")
        else:
            self.conveyor(ConveyorBeltState(power=100.0))
            self.start_spawn()


def main():
    parts = int(sys.argv[1]) if len(sys.argv) > 1 else 2
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node("lecture7_belt_pick")
    BeltPicker(parts)
    rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)(ConveyorBeltState(power=100.0))
    rospy.ServiceProxy("/start_spawn", Empty)()
    rospy.spin()


if __name__ == "__main__":
    main()
