"""One quaternion normaliser: tf.transformations and geometry messages refuse a zero
quaternion with the same ConfigError and normalize any other."""

import math

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm.messages import Point, Pose, Quaternion
from omtp_drake.ros.tf import transformations
from omtp_drake.ros.tf.convert import rigid


def test_a_zero_quaternion_is_refused_the_same_way_by_tf_and_by_messages():
    with pytest.raises(ConfigError, match=r"set w = 1 for no rotation") as by_tf:
        transformations.euler_from_quaternion([0.0, 0.0, 0.0, 0.0])
    with pytest.raises(ConfigError, match=r"set w = 1 for no rotation"):
        rigid(Pose(Point(0.0, 0.0, 0.0), Quaternion(0.0, 0.0, 0.0, 0.0)))
    assert "(0.0, 0.0, 0.0, 0.0)" in str(by_tf.value)


def test_a_scaled_quaternion_is_normalized_by_both():
    half = math.sqrt(0.5)
    _, _, yaw = transformations.euler_from_quaternion([0.0, 0.0, 3 * half, 3 * half])
    assert yaw == pytest.approx(math.pi / 2)
    X = rigid(Pose(Point(1.0, 2.0, 3.0), Quaternion(0.0, 0.0, 3 * half, 3 * half)))
    assert X.rotation().col(0) == pytest.approx([0.0, 1.0, 0.0])
