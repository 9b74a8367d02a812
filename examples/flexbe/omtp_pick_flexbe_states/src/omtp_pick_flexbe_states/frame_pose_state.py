#!/usr/bin/env python
import rospy
import tf2_ros
from flexbe_core import EventState, Logger
from geometry_msgs.msg import PoseStamped


class FramePoseState(EventState):
    '''
    The pose of a tf frame (e.g. a bin's base link) in ref_frame.

    -- frame        string  The frame, e.g. bin_2_base_link.
    -- ref_frame    string  The frame of the output pose.

    #> pose         PoseStamped     The frame's pose.

    <= continue             Found.
    <= failed               Unknown frame.
    '''

    def __init__(self, frame, ref_frame='world'):
        super(FramePoseState, self).__init__(outcomes=['continue', 'failed'], output_keys=['pose'])
        self._frame = frame
        self._ref_frame = ref_frame
        self._buffer = tf2_ros.Buffer()
        self._listener = tf2_ros.TransformListener(self._buffer)
        self._pose = None

    def on_enter(self, userdata):
        try:
            t = self._buffer.lookup_transform(self._ref_frame, self._frame, rospy.Time(0), rospy.Duration(1.0))
        except Exception as e:
            Logger.logwarn('No transform to %s: %s' % (self._frame, e))
            self._pose = None
            return
        self._pose = PoseStamped()
        self._pose.header.frame_id = self._ref_frame
        self._pose.pose.position.x = t.transform.translation.x
        self._pose.pose.position.y = t.transform.translation.y
        self._pose.pose.position.z = t.transform.translation.z
        self._pose.pose.orientation = t.transform.rotation

    def execute(self, userdata):
        if self._pose is None:
            return 'failed'
        userdata.pose = self._pose
        return 'continue'
