#!/usr/bin/env python3
"""The Conveyor Pick of examples/flexbe as a plain rospy script: the same services, topics,
/compute_ik and /move_group calls in the same order, polled at FlexBE's 10 Hz, without the
FlexBE engine (bench_flexbe.py compares the two).

    omtp-drake ros-run bench/flexbe_pick_ros.py [PARTS] --scenario lecture7_flexbe
"""

import math
import sys
import xml.etree.ElementTree as ET

import actionlib
import moveit_commander
import rospy
import tf2_geometry_msgs
import tf2_ros
from geometry_msgs.msg import PoseStamped, Quaternion
from moveit_msgs.msg import Constraints, JointConstraint, MoveGroupAction, MoveGroupGoal
from moveit_msgs.srv import GetPositionIK, GetPositionIKRequest
from omtp_gazebo.msg import ConveyorBeltState, LogicalCameraImage, Proximity
from omtp_gazebo.srv import ConveyorBeltControl, VacuumGripperControl
from sensor_msgs.msg import JointState
from std_srvs.srv import Empty
from tf.transformations import quaternion_from_euler

TOOL = "vacuum_gripper1_suction_cup"


class Picker:
    def __init__(self):
        self.rate = rospy.Rate(10)
        self.move_group = actionlib.SimpleActionClient("move_group", MoveGroupAction)
        self.ik = rospy.ServiceProxy("/compute_ik", GetPositionIK)
        self.conveyor = rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)
        self.gripper = rospy.ServiceProxy("/gripper1/control", VacuumGripperControl)
        self.start_spawn = rospy.ServiceProxy("/start_spawn", Empty)
        self.stop_spawn = rospy.ServiceProxy("/stop_spawn", Empty)
        self.tf_buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.tf_buffer)
        srdf = rospy.get_param("/robot_description_semantic", None)
        self.srdf = ET.fromstring(srdf) if srdf else None
        self.group = None if srdf else moveit_commander.MoveGroupCommander("robot1")
        self.beam = None
        self.image = None
        rospy.Subscriber("/break_beam_sensor", Proximity, self.on_beam)
        rospy.Subscriber("/omtp/logical_camera", LogicalCameraImage, self.on_image)

    def on_beam(self, msg):
        self.beam = msg

    def on_image(self, msg):
        self.image = msg

    def wait(self, seconds):
        end = rospy.get_time() + seconds
        while rospy.get_time() <= end:
            self.rate.sleep()

    def move_joints(self, names, values):
        goal = MoveGroupGoal()
        goal.request.group_name = "robot1"
        goal.request.max_velocity_scaling_factor = 1.0
        goal.request.goal_constraints.append(
            Constraints(
                joint_constraints=[
                    JointConstraint(joint_name=n, position=v, weight=1.0) for n, v in zip(names, values)
                ]
            )
        )
        self.move_group.send_goal(goal)
        while self.move_group.get_state() in (actionlib.GoalStatus.PENDING, actionlib.GoalStatus.ACTIVE):
            self.rate.sleep()
        return self.move_group.get_result().error_code.val == 1

    def named(self, name):
        if self.srdf is None:  # ros-run without an SRDF parameter: MoveIt's named targets
            values = self.group.get_named_target_values(name)
            return self.move_joints(list(values), list(values.values()))
        for state in self.srdf.iter("group_state"):
            if state.get("name") == name:
                joints = [(j.get("name"), float(j.get("value"))) for j in state.iter("joint")]
                return self.move_joints([n for n, _ in joints], [v for _, v in joints])
        return False

    def above(self, pose, offset):
        target = PoseStamped()
        target.header = pose.header
        target.pose.position.x = pose.pose.position.x
        target.pose.position.y = pose.pose.position.y
        target.pose.position.z = pose.pose.position.z + offset
        target.pose.orientation = Quaternion(*quaternion_from_euler(math.pi, 0.0, 0.0))
        request = GetPositionIKRequest()
        request.ik_request.group_name = "robot1"
        request.ik_request.robot_state.joint_state = rospy.wait_for_message(
            "/robot1/joint_states", JointState, 1.0
        )
        request.ik_request.ik_link_name = TOOL
        request.ik_request.pose_stamped = target
        request.ik_request.avoid_collisions = True
        solution = self.ik(request)
        if solution.error_code.val != 1:
            return False
        return self.move_joints(solution.solution.joint_state.name, solution.solution.joint_state.position)

    def part_pose(self):
        transform = self.tf_buffer.lookup_transform(
            "world", "logical_camera_frame", rospy.Time(0), rospy.Duration(1.0)
        )
        self.image = None
        while True:
            if self.image is not None:
                for model in self.image.models:
                    if model.type == "object":
                        seen = PoseStamped()
                        seen.header.frame_id = "logical_camera_frame"
                        seen.header.stamp = rospy.Time.now()
                        seen.pose = model.pose
                        return tf2_geometry_msgs.do_transform_pose(seen, transform)
            self.rate.sleep()

    def bin_pose(self):
        t = self.tf_buffer.lookup_transform("world", "bin_2_base_link", rospy.Time(0), rospy.Duration(1.0))
        pose = PoseStamped()
        pose.header.frame_id = "world"
        pose.pose.position.x = t.transform.translation.x
        pose.pose.position.y = t.transform.translation.y
        pose.pose.position.z = t.transform.translation.z
        return pose

    def pick(self, parts):
        if not self.named("R1Home"):
            return "failed"
        picked = 0
        while picked < parts:
            self.conveyor(ConveyorBeltState(power=100.0))
            self.start_spawn()
            self.beam = None
            while self.beam is None or not self.beam.object_detected:
                self.beam = None
                while self.beam is None:
                    self.rate.sleep()
            self.stop_spawn()
            self.wait(0.5)
            part = self.part_pose()
            rospy.loginfo("part at %s", part.pose.position)
            self.gripper(True)
            for offset in (0.4, 0.16):
                if not self.above(part, offset):
                    return "failed"
            self.wait(0.3)
            if not self.above(part, 0.5) or not self.above(self.bin_pose(), 0.8):
                return "failed"
            self.gripper(False)
            self.wait(0.5)
            picked += 1
            rospy.loginfo("parts in bin 2: %d", picked)
        return "finished" if self.named("R1Home") else "failed"


if __name__ == "__main__":
    rospy.init_node("flexbe_pick_ros")
    outcome = Picker().pick(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
    rospy.loginfo("outcome: %s", outcome)
    sys.exit(0 if outcome == "finished" else 1)
