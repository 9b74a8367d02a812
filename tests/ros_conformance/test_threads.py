"""rospy's threads: a script's ``threading.Thread`` calls services, sleeps and reads
parameters in simulated time, taking turns with the main thread (one runs at a time),
the same way every run."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

A4 = "lecture6_assignment4"
#: rospy.sleep(0.25), then a GetModelState call that takes ros_latency.service (5 ms).
WATCH_PERIOD = 0.25 + 0.005


def _comparable(report):
    data = report.to_dict() if hasattr(report, "to_dict") else dict(report)
    return {k: v for k, v in data.items() if k not in ("wall_time_s", "replay")}


def test_a_service_calling_thread_beside_moveit_moves_the_same_way_every_run(course_run, tmp_path):
    report, data = course_run("gripper_watch_thread.py", scenario=A4, out_arg=True)
    assert report.ok, report.summary()
    assert report.ledger["in_bin"]["bin_1"] == 1 and report.ledger["parts"] == {"object_1": "in_bin:bin_1"}
    calls = data["calls"]
    # One call every 0.25 s of sleep plus the call's 5 ms, on time during the MoveIt moves too,
    # until the main thread's last line; each answered (object_1 is in the world).
    assert len(calls) == int(data["end"] / WATCH_PERIOD)
    assert [t for t, _, _ in calls] == pytest.approx([WATCH_PERIOD * k for k in range(1, len(calls) + 1)])
    assert all(success for _, success, _ in calls)
    assert calls[-1][2] == pytest.approx(0.2, abs=0.05)  # the part lies in bin 1 (its centre ~0.2 m up)

    # The same script again, as `omtp-drake ros-run` in its own process: the same run, a clean exit.
    out, result = tmp_path / "again.json", tmp_path / "report.json"
    script = str(Path(__file__).parent / "scripts" / "gripper_watch_thread.py")
    done = subprocess.run(
        [sys.executable, "-m", "omtp_drake.grading.cli", "ros-run", script, str(out), "--scenario", A4, "-q"]
        + ["--json", str(result)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "terminate called" not in done.stderr and "Traceback" not in done.stderr
    assert json.loads(out.read_text()) == data
    assert _comparable(json.loads(result.read_text())) == _comparable(report)


def test_a_thread_ends_with_the_script_and_a_non_daemon_one_is_waited_for(course_run, tmp_path):
    ended = tmp_path / "ended.json"
    report, data = course_run(
        f"""\
        import json, sys, threading
        import rospy
        rospy.init_node("threads")
        ticks = []

        def ticker():
            try:
                while not rospy.is_shutdown():
                    rospy.sleep(0.1)
                    ticks.append(round(rospy.get_time(), 6))
            except rospy.ROSInterruptException:
                ticks.append("interrupted")
            json.dump(ticks, open({str(ended)!r}, "w"))

        def setter():
            rospy.sleep(1.0)
            rospy.set_param("/late", rospy.get_time())

        threading.Thread(target=ticker, daemon=True).start()
        late = threading.Thread(target=setter)
        late.start()
        late.join(0.25)  # simulated seconds, as rospy's clock
        joined_at = rospy.get_time()
        rospy.sleep(0.3)
        json.dump({{"joined_at": joined_at, "alive": late.is_alive(), "now": rospy.get_time()}},
                  open(sys.argv[1], "w"))
        """,
        scenario="lecture6_assignment3",
        out_arg=True,
    )
    assert report.ok, report.summary()
    assert data == {"joined_at": pytest.approx(0.25), "alive": True, "now": pytest.approx(0.55)}
    # Python waits for the non-daemon thread: the run goes on to its end at 1.0 s.
    assert report.sim_time_s == pytest.approx(1.0)
    ticks = json.loads(ended.read_text())
    # The daemon ticked every 0.1 s until then; at the script's end its sleep was interrupted.
    assert ticks[:-1] == pytest.approx([0.1 * k for k in range(1, 11)])
    assert ticks[-1] == "interrupted"


def test_a_thread_that_raises_is_reported_and_the_main_thread_goes_on(course_run):
    report, data = course_run(
        """\
        import json, sys, threading
        import rospy
        rospy.init_node("threads")

        def broken():
            rospy.sleep(0.2)
            raise ValueError("no such part")

        worker = threading.Thread(target=broken, name="watcher")
        worker.start()
        worker.join()
        json.dump({"t": rospy.get_time()}, open(sys.argv[1], "w"))
        """,
        scenario="lecture6_assignment3",
        out_arg=True,
    )
    assert data == {"t": pytest.approx(0.2)}
    assert report.thread_errors == ["watcher: ValueError: no such part"]
    assert not report.ok and "thread error: watcher: ValueError: no such part" in report.summary()


def test_threads_publish_subscribe_read_parameters_and_look_up_transforms(course_run):
    """A thread echoes the main thread's messages on its own topic, reads a parameter and
    waits for a transform with a timeout; the main thread counts the echoes: each comes at
    the time its message was sent, in order."""
    report, data = course_run(
        """\
        import json, sys, threading
        import rospy, tf2_ros
        from std_msgs.msg import Float64
        rospy.init_node("echo")
        rospy.set_param("~gain", 2.0)
        out = {"echoes": []}

        def echo_node():
            gain = rospy.get_param("/echo/gain")
            buffer = tf2_ros.Buffer()
            tf2_ros.TransformListener(buffer)
            bin_pose = buffer.lookup_transform("world", "bin_1_base_link", rospy.Time(0), rospy.Duration(1.0))
            out["bin"] = [bin_pose.transform.translation.x, bin_pose.transform.translation.y]
            echo = rospy.Publisher("/echo", Float64, queue_size=10)
            rospy.Subscriber("/ping", Float64, lambda m: echo.publish(Float64(m.data * gain)))
            rospy.spin()

        threading.Thread(target=echo_node, daemon=True).start()
        rospy.Subscriber("/echo", Float64, lambda m: out["echoes"].append([rospy.get_time(), m.data]))
        ping = rospy.Publisher("/ping", Float64, queue_size=10)
        rospy.sleep(0.5)
        for k in range(1, 4):
            ping.publish(Float64(k))
            rospy.sleep(0.2)
        json.dump(out, open(sys.argv[1], "w"))
        """,
        scenario="lecture6_assignment3",
        out_arg=True,
    )
    assert report.ok, report.summary()
    assert data["bin"] == pytest.approx([-8.0, -2.2], abs=1e-9)
    assert [tuple(e) for e in data["echoes"]] == [
        pytest.approx((0.5, 2.0)),
        pytest.approx((0.7, 4.0)),
        pytest.approx((0.9, 6.0)),
    ]


def test_a_daemon_thread_that_swallows_the_interrupt_is_left_where_it_blocks(tmp_path):
    """As a daemon thread at Python's exit: the run ends, the process exits cleanly."""
    script = tmp_path / "stubborn.py"
    script.write_text(
        "import threading\nimport rospy\nrospy.init_node('stubborn')\n\n"
        "def stubborn():\n    while True:\n        try:\n            rospy.sleep(0.1)\n"
        "        except:\n            pass\n\n"
        "threading.Thread(target=stubborn, daemon=True).start()\nrospy.sleep(0.35)\n"
    )
    result = tmp_path / "report.json"
    done = subprocess.run(
        [sys.executable, "-m", "omtp_drake.grading.cli", "ros-run", str(script)]
        + ["--scenario", "lecture6_assignment3", "-q", "--json", str(result)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "terminate called" not in done.stderr
    report = json.loads(result.read_text())
    assert report["sim_time_s"] == pytest.approx(0.35) and report["thread_errors"] == []


FLEXBE_THREAD_STATE = """\
import threading

import rospy
from flexbe_core import EventState, Logger
from omtp_gazebo.msg import ConveyorBeltState
from omtp_gazebo.srv import ConveyorBeltControl


class PulseBeltState(EventState):
    '''Pulses the belt from a thread while the behaviour goes on.'''

    def __init__(self):
        super(PulseBeltState, self).__init__(outcomes=['started'])

    def on_enter(self, userdata):
        threading.Thread(target=self._pulse, daemon=True).start()

    def _pulse(self):
        belt = rospy.ServiceProxy('/omtp/conveyor/control', ConveyorBeltControl)
        for power in (100, 0):
            rospy.sleep(0.5)
            belt(ConveyorBeltState(power=power))
            Logger.loginfo('belt %d' % power)

    def execute(self, userdata):
        return 'started'
"""

FLEXBE_THREAD_BEHAVIOR = """\
from flexbe_core import Behavior, Autonomy, OperatableStateMachine
from flexbe_states.wait_state import WaitState
from pulse_states.pulse_belt_state import PulseBeltState


class PulseSM(Behavior):
    def __init__(self):
        super(PulseSM, self).__init__()
        self.name = 'Pulse'

    def create(self):
        _state_machine = OperatableStateMachine(outcomes=['finished'])
        with _state_machine:
            OperatableStateMachine.add('pulse', PulseBeltState(), transitions={'started': 'wait'},
                                       autonomy={'started': Autonomy.Off})
            OperatableStateMachine.add('wait', WaitState(wait_time=2.0), transitions={'done': 'finished'},
                                       autonomy={'done': Autonomy.Off})
        return _state_machine
"""


def test_a_flexbe_state_that_starts_a_thread(tmp_path):
    from omtp_drake.ros.flexbe import run_behavior

    files = {
        "pulse_states/src/pulse_states/pulse_belt_state.py": FLEXBE_THREAD_STATE,
        "pulse_behaviors/src/pulse_behaviors/pulse_sm.py": FLEXBE_THREAD_BEHAVIOR,
        "pulse_behaviors/manifest/pulse.xml": '<behavior name="Pulse">'
        '<executable package_path="pulse_behaviors.pulse_sm" class="PulseSM" /></behavior>',
    }
    for package in ("pulse_states", "pulse_behaviors"):
        (tmp_path / package / "src" / package).mkdir(parents=True)
        (tmp_path / package / "src" / package / "__init__.py").write_text("")
        (tmp_path / package / "package.xml").write_text(
            f"<package format='2'><name>{package}</name><version>0.0.1</version><description>x</description>"
            "<maintainer email='s@example.org'>s</maintainer><license>BSD</license></package>"
        )
    for rel, text in files.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    report = run_behavior("Pulse", [tmp_path], scenario="lecture7_flexbe", timeout=10.0)
    assert report.outcome == "finished" and report.ok, report.summary()
    pulses = [(x["time"], x["text"]) for x in report.logs if x["text"].startswith("belt")]
    # Entered at 0 s (FlexBE's first tick); each pulse after 0.5 s of sleep and the call's 5 ms.
    start = report.trace[0]["entered"]
    assert [text for _, text in pulses] == ["belt 100", "belt 0"]
    assert [t - start for t, _ in pulses] == pytest.approx([0.505, 1.01])
