#!/usr/bin/env python
import inspect

import rospy
import rostopic
import tf2_geometry_msgs
import tf2_ros
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxySubscriberCached
from geometry_msgs.msg import PoseStamped


class PartPoseState(EventState):
    '''
    The pose of the first part ('object') a logical camera sees, in ref_frame.

    -- ref_frame        string  Frame of the output pose, e.g. world.
    -- camera_topic     string  The camera's topic, e.g. /omtp/logical_camera.
    -- camera_frame     string  The camera's frame, e.g. logical_camera_frame.

    #> pose             PoseStamped     The part's pose.

    <= continue                 A part was seen.
    <= failed                   No camera topic or no transform.
    '''

    def __init__(self, ref_frame, camera_topic, camera_frame):
        super(PartPoseState, self).__init__(outcomes=['continue', 'failed'], output_keys=['pose'])
        self._ref_frame = ref_frame
        self._topic = camera_topic
        self._camera_frame = camera_frame
        self._tf_buffer = tf2_ros.Buffer(rospy.Duration(10.0))
        self._tf_listener = tf2_ros.TransformListener(self._tf_buffer)
        msg_path, msg_topic, _ = rostopic.get_topic_type(self._topic)
        self._connected = msg_topic == self._topic
        if self._connected:
            self._sub = ProxySubscriberCached({self._topic: self._msg_class(msg_path)})
        else:
            Logger.logwarn('Camera topic %s is not available' % self._topic)
        self._transform = None

    def _msg_class(self, msg_path):
        package, name = msg_path.split('/')
        module = __import__(package + '.msg', fromlist=[name])
        return dict(inspect.getmembers(module, inspect.isclass))[name]

    def on_enter(self, userdata):
        try:
            self._transform = self._tf_buffer.lookup_transform(
                self._ref_frame, self._camera_frame, rospy.Time(0), rospy.Duration(1.0))
        except Exception as e:
            Logger.logwarn('Could not look up the camera transform: %s' % e)
            self._transform = None
        if self._connected:
            self._sub.remove_last_msg(self._topic)  # only an image taken from now on

    def execute(self, userdata):
        if not self._connected or self._transform is None:
            return 'failed'
        if not self._sub.has_msg(self._topic):
            return None
        image = self._sub.get_last_msg(self._topic)
        for model in image.models:
            if model.type == 'object':
                seen = PoseStamped()
                seen.header.frame_id = self._camera_frame
                seen.header.stamp = rospy.Time.now()
                seen.pose = model.pose
                userdata.pose = tf2_geometry_msgs.do_transform_pose(seen, self._transform)
                return 'continue'
        return None
