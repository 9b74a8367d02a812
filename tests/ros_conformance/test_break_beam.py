"""The break beam's topics as the course's proximity-ray plugin names and publishes them
(omtp_gazebo/src/plugins/ROSProximityRayPlugin.cc, ProximityRayPlugin.cc; the sensor
``break_beam_sensor`` of omtp_support/urdf/break_beam/break_beam.gazebo.xacro)."""

import pytest

#: Lecture 7's belt without the cell's own stop-on-beam: only the script stops it.
BELT_WITHOUT_AUTO_STOP = """\
base: lecture7_conveyor
conveyor:
  power: 0.0
  stop_on_beam: false
"""

BEAM_Y = 1.9  # the beam crosses the belt at y = 1.9 (reference section 1)
PART_HALF = 0.1


@pytest.fixture
def belt_scenario(tmp_path):
    path = tmp_path / "belt_without_auto_stop.yaml"
    path.write_text(BELT_WITHOUT_AUTO_STOP)
    return path


def test_a_change_subscriber_stops_the_belt_with_the_part_at_the_beam(course_run, belt_scenario):
    report, data = course_run("breakbeam_conveyor_stop.py", scenario=belt_scenario, out_arg=True, timeout=30)
    assert report.exception is None and report.callback_errors == []
    assert len(data["stops"]) == 1
    # /start_spawn's timer spawns one period (3 s) after the call, at y = 2.5 on a belt
    # at 0.2 m/s: the leading face reaches the beam 2.5 s later.
    assert data["stops"][0] == pytest.approx(3.0 + 2.5, abs=0.25)
    x, y, _z = data["part_world_xyz"]
    # Stopped with its leading face just past the beam (without the stop: y < 1.6 by the end).
    assert BEAM_Y < y <= BEAM_Y + PART_HALF + 0.005
    assert x == pytest.approx(1.2, abs=0.01)
    assert report.ledger["on_belt"] == 1 and report.ledger["disposed"] == 0
    beam = data["beam"]
    assert beam["object_detected"] is True
    assert (beam["min_range"], beam["max_range"]) == pytest.approx((0.1, 0.6))
    assert beam["frame_id"] == "break_beam_sensor_frame"


STATE_AND_LATCH = """\
import json, sys
import rospy
from omtp_gazebo.msg import Proximity
from std_srvs.srv import Empty

states = []

def on_state(msg):
    states.append([msg.header.stamp.to_sec(), msg.object_detected])

rospy.init_node('beam_listener')
rospy.Subscriber('/break_beam_sensor', Proximity, on_state)
rospy.sleep(1.0)
before = len(states)
try:
    rospy.wait_for_message('/break_beam_sensor_change', Proximity, timeout=0.5)
    change_before_part = True
except rospy.ROSException:
    change_before_part = False
rospy.ServiceProxy('/start_spawn', Empty)()  # the first part one period (3 s) later
rospy.sleep(8.0)
late = []
rospy.Subscriber('/break_beam_sensor_change', Proximity, lambda m: late.append(m.header.stamp.to_sec()))
rospy.sleep(0.01)
json.dump({'states': states, 'before': before, 'change_before_part': change_before_part,
           'late': late, 't': rospy.get_time()}, open(sys.argv[1], 'w'))
"""


def test_state_topic_every_sample_change_topic_only_changes_and_latched(course_run):
    report, data = course_run(STATE_AND_LATCH, scenario="lecture7_conveyor", out_arg=True, timeout=30)
    assert report.exception is None
    # 10 Hz: one state message per 0.1 s sample, stamped at the sample.
    assert 9 <= data["before"] <= 11
    stamps = [s for s, _ in data["states"]]
    assert all(b - a == pytest.approx(0.1) for a, b in zip(stamps, stamps[1:]))
    assert [d for _, d in data["states"][: data["before"]]] == [False] * data["before"]
    # The plugin starts at "not detected": nothing on the change topic until a part arrives.
    assert data["change_before_part"] is False
    assert any(d for _, d in data["states"])
    # Latched: a subscriber that comes after the detection gets it at once, with its stamp.
    assert len(data["late"]) == 1 and data["late"][0] < data["t"] - 1.0
