"""FlexBE's engine semantics, without a cell: transitions, userdata, autonomy, containers,
errors, behaviours and parameters, in a clock that only moves when the engine sleeps.

States and behaviours are written as FlexBE users write them (EventState subclasses,
``with`` blocks, ``OperatableStateMachine.add``)."""

from __future__ import annotations

import pytest

from omtp_drake.ros.flexbe.behavior import Behavior
from omtp_drake.ros.flexbe.containers import ConcurrencyContainer, PriorityContainer
from omtp_drake.ros.flexbe.context import (
    AUTONOMY_LEVELS,
    FlexbeRun,
    ManualClock,
    OperatorRequired,
    StateFailed,
    active_run,
)
from omtp_drake.ros.flexbe.engine import Autonomy, EventState, Logger, OperatableStateMachine
from omtp_drake.ros.flexbe.states import (
    CalculationState,
    CheckConditionState,
    DecisionState,
    FlexibleCalculationState,
    InputState,
    LogKeyState,
    LogState,
    OperatorDecisionState,
    WaitState,
)
from omtp_drake.ros.flexbe.userdata import StateMachineError, UserDataError


@pytest.fixture
def run():
    with active_run(FlexbeRun(ManualClock())) as r:
        yield r


class CountState(EventState):
    """Counts its calls; returns 'done' on the n-th execute."""

    def __init__(self, n=1):
        super().__init__(outcomes=["done", "failed"], input_keys=["count"], output_keys=["count"])
        self._n = n
        self.events = []

    def on_start(self):
        self.events.append("start")

    def on_enter(self, userdata):
        self.events.append("enter")
        self._calls = 0

    def execute(self, userdata):
        self._calls += 1
        if self._calls >= self._n:
            userdata.count = userdata.count + 1
            return "done"

    def on_exit(self, userdata):
        self.events.append("exit")

    def on_stop(self):
        self.events.append("stop")


def test_transitions_events_and_ticks_at_10_hz(run):
    a, b = CountState(3), CountState(1)
    sm = OperatableStateMachine(outcomes=["finished", "failed"])
    sm.userdata.count = 0
    with sm:
        OperatableStateMachine.add("a", a, transitions={"done": "b", "failed": "failed"})
        OperatableStateMachine.add("b", b, transitions={"done": "finished", "failed": "failed"})
    sm.confirm("test")
    assert sm.spin() == "finished"
    sm.destroy()
    assert a.events == ["start", "enter", "exit", "stop"]
    assert sm.userdata.count == 0  # the container's defaults are not written back
    trace = [(t.path, t.outcome, round(t.entered, 3), round(t.left, 3)) for t in run.trace]
    # rospy.Rate: "a" (made at t=0) ticks at 0, 0.1, 0.2; "b" is entered at 0.2 and ticks at once
    assert trace == [("/a", "done", 0.0, 0.2), ("/b", "done", 0.2, 0.2)]


def test_wait_state_is_done_the_first_tick_after_its_time(run):
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("wait", WaitState(wait_time=1.0), transitions={"done": "finished"})
    assert sm.spin() == "finished"
    assert run.time == pytest.approx(1.1)


class WriteState(EventState):
    def __init__(self):
        super().__init__(outcomes=["done"], output_keys=["out"])

    def execute(self, userdata):
        userdata.out = [1, 2]
        return "done"


class ReadState(EventState):
    def __init__(self, mutate=False):
        super().__init__(outcomes=["done"], input_keys=["value"])
        self._mutate = mutate
        self.seen = None

    def execute(self, userdata):
        self.seen = list(userdata.value)
        if self._mutate:
            userdata.value.append(3)
        return "done"


def _two_states(second, remap):
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add(
            "write", WriteState(), transitions={"done": "read"}, remapping={"out": "shared"}
        )
        OperatableStateMachine.add("read", second, transitions={"done": "finished"}, remapping=remap)
    return sm


def test_remapping_carries_output_to_input(run):
    reader = ReadState()
    assert _two_states(reader, {"value": "shared"}).spin() == "finished"
    assert reader.seen == [1, 2]


def test_reading_an_undeclared_or_missing_key_fails_the_state(run):
    class Sneaky(EventState):
        def __init__(self):
            super().__init__(outcomes=["done"])

        def execute(self, userdata):
            return "done" if userdata.shared else None

    with pytest.raises(StateFailed) as e:
        _two_states(Sneaky(), {}).spin()
    assert e.value.path == "/read"
    assert isinstance(e.value.error, UserDataError)
    assert "declare it as input key" in str(e.value.error)
    assert any(x.severity == "error" and "Failed to execute state read" in x.text for x in run.logs)
    with pytest.raises(StateFailed, match="No data found for key 'value'"):
        _two_states(ReadState(), {}).spin()


def test_changing_an_input_only_key_in_place_is_an_error(run):
    with pytest.raises(StateFailed, match="Illegally modified input-only key 'value'"):
        _two_states(ReadState(mutate=True), {"value": "shared"}).spin()


def test_writing_an_undeclared_output_key_is_an_error(run):
    class Writer(EventState):
        def __init__(self):
            super().__init__(outcomes=["done"])

        def execute(self, userdata):
            userdata.x = 1
            return "done"

    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("w", Writer(), transitions={"done": "finished"})
    with pytest.raises(StateFailed, match="declare it as output key"):
        sm.spin()


def test_nested_container_outputs_reach_the_parent(run):
    inner = OperatableStateMachine(outcomes=["ok"], input_keys=["count"], output_keys=["count"])
    with inner:
        OperatableStateMachine.add("inc", CountState(1), transitions={"done": "ok", "failed": "ok"})
    sm = OperatableStateMachine(outcomes=["finished"])
    sm.userdata.n = 41
    with sm:
        OperatableStateMachine.add("inner", inner, transitions={"ok": "check"}, remapping={"count": "n"})
        OperatableStateMachine.add(
            "check",
            CheckConditionState(predicate=lambda n: n == 42),
            transitions={"true": "finished", "false": "check_failed"},
            remapping={"input_value": "n"},
        )
        OperatableStateMachine.add("check_failed", LogState("n is not 42"), transitions={"done": "check"})
    assert sm.spin() == "finished"
    assert [t.path for t in run.trace] == ["/inner", "/inner/inc", "/check"]


def test_a_missing_transition_target_is_reported_before_running(run):
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("log", LogState("x"), transitions={"done": "nowhere"})
    with pytest.raises(StateMachineError, match="Transition target 'nowhere'"):
        sm.spin()


def test_an_unregistered_outcome_fails_the_state(run):
    class Odd(EventState):
        def __init__(self):
            super().__init__(outcomes=["done", "odd"])

        def execute(self, userdata):
            return "odd"

    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("odd", Odd(), transitions={"done": "finished"})
    with pytest.raises(StateFailed, match="Returned outcome 'odd' is not registered as transition"):
        sm.spin()


def _autonomy_machine(required):
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add(
            "log", LogState("hi"), transitions={"done": "finished"}, autonomy={"done": required}
        )
    return sm


@pytest.mark.parametrize(
    "level, required, passes",
    [
        ("full", Autonomy.High, True),
        ("high", Autonomy.High, False),
        ("high", Autonomy.Low, True),
        ("low", Autonomy.Off, True),
        ("off", Autonomy.Off, False),
        ("full", Autonomy.Full, False),
    ],
)
def test_autonomy_levels(run, level, required, passes):
    run.autonomy = AUTONOMY_LEVELS[level]
    sm = _autonomy_machine(required)
    if passes:
        assert sm.spin() == "finished"
    else:
        with pytest.raises(OperatorRequired, match=r"state /log returned 'done', which needs autonomy"):
            sm.spin()


def test_operator_decision_takes_the_suggestion_or_needs_an_operator(run):
    sm = OperatableStateMachine(outcomes=["left", "right"])
    with sm:
        OperatableStateMachine.add(
            "ask",
            OperatorDecisionState(outcomes=["left", "right"], hint="which way?", suggestion="right"),
            transitions={"left": "left", "right": "right"},
            autonomy={"left": Autonomy.Full, "right": Autonomy.High},
        )
    assert sm.spin() == "right"
    assert ("hint", "which way?") in [(x.severity, x.text) for x in run.logs]
    sm = OperatableStateMachine(outcomes=["left"])
    with sm:
        OperatableStateMachine.add(
            "ask", OperatorDecisionState(outcomes=["left"]), transitions={"left": "left"}
        )
    with pytest.raises(OperatorRequired, match="waits for an operator to choose one of left"):
        sm.spin()
    sm = OperatableStateMachine(outcomes=["received", "aborted", "no_connection", "data_error"])
    with sm:
        outcomes = ["received", "aborted", "no_connection", "data_error"]
        OperatableStateMachine.add(
            "input", InputState(request=0, message="pose?"), transitions={o: o for o in outcomes}
        )
    with pytest.raises(OperatorRequired, match="InputState /input asks the operator"):
        sm.spin()


def test_concurrency_container_ends_on_its_first_satisfied_condition(run):
    cc = ConcurrencyContainer(
        outcomes=["both", "failed"],
        conditions=[("both", [("short", "done"), ("long", "done")])],
    )
    with cc:
        OperatableStateMachine.add("short", WaitState(wait_time=0.5), transitions={"done": "both"})
        OperatableStateMachine.add("long", WaitState(wait_time=1.0), transitions={"done": "both"})
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("cc", cc, transitions={"both": "finished", "failed": "finished"})
    assert sm.spin() == "finished"
    # Each branch ticks when its period is up: first at 0.1 (made at 0), then every 0.1 s.
    entered = {t.path: t.entered for t in run.trace}
    left = {t.path: t.left for t in run.trace}
    assert entered["/cc/short"] == entered["/cc/long"] == pytest.approx(0.1)
    assert left["/cc/short"] == pytest.approx(0.7)
    assert left["/cc/long"] == pytest.approx(1.2)
    assert run.time == pytest.approx(1.2)


def test_priority_container_runs_alone(run):
    ticks = []

    class Tick(EventState):
        def __init__(self, name, n):
            super().__init__(outcomes=["done"])
            self._label, self._n = name, n

        def on_enter(self, userdata):
            self._k = 0

        def execute(self, userdata):
            ticks.append((self._label, round(run.time, 2)))
            self._k += 1
            return "done" if self._k >= self._n else None

    prio = PriorityContainer(outcomes=["done"])
    with prio:
        OperatableStateMachine.add("urgent", Tick("urgent", 3), transitions={"done": "done"})
    cc = ConcurrencyContainer(outcomes=["done"], conditions=[("done", [("prio", "done"), ("bg", "done")])])
    with cc:
        OperatableStateMachine.add("prio", prio, transitions={"done": "done"})
        OperatableStateMachine.add("bg", Tick("bg", 2), transitions={"done": "done"})
    sm = OperatableStateMachine(outcomes=["finished"])
    with sm:
        OperatableStateMachine.add("cc", cc, transitions={"done": "finished"})
    assert sm.spin() == "finished"
    first_bg = min(i for i, (label, _t) in enumerate(ticks) if label == "bg")
    assert [label for label, _t in ticks[:first_bg]] == ["urgent"] * 3
    assert run.priority_path is None


def test_calculation_states_and_logs(run):
    sm = OperatableStateMachine(outcomes=["finished"])
    sm.userdata.a, sm.userdata.b = 2, 3
    with sm:
        OperatableStateMachine.add(
            "sum",
            FlexibleCalculationState(calculation=lambda a, b: a + b, input_keys=["a", "b"]),
            transitions={"done": "square"},
            remapping={"output_value": "s"},
        )
        OperatableStateMachine.add(
            "square",
            CalculationState(calculation=lambda x: x * x),
            transitions={"done": "decide"},
            remapping={"input_value": "s", "output_value": "sq"},
        )
        OperatableStateMachine.add(
            "decide",
            DecisionState(outcomes=["big", "small"], conditions=lambda v: "big" if v > 20 else "small"),
            transitions={"big": "log", "small": "finished"},
            remapping={"input_value": "sq"},
        )
        OperatableStateMachine.add(
            "log",
            LogKeyState(text="square: {}", severity=Logger.REPORT_WARN),
            transitions={"done": "finished"},
            remapping={"data": "sq"},
        )
    assert sm.spin() == "finished"
    assert ("warn", "square: 25") in [(x.severity, x.text) for x in run.logs]


class Sub(Behavior):
    def __init__(self):
        super().__init__()
        self.name = "Sub"
        self.add_parameter("factor", 2)

    def create(self):
        _sm = OperatableStateMachine(outcomes=["done"], input_keys=["x"], output_keys=["y"])
        _sm.userdata.x = 100  # a default the parent overrides
        with _sm:
            OperatableStateMachine.add(
                "times",
                CalculationState(calculation=lambda x: x * self.factor),
                transitions={"done": "done"},
                remapping={"input_value": "x", "output_value": "y"},
            )
        return _sm


class Top(Behavior):
    def __init__(self):
        super().__init__()
        self.name = "Top"
        self.add_parameter("start", 1.5)
        self.add_parameter("verbose", False)
        self.add_behavior(Sub, "Sub")

    def create(self):
        _sm = OperatableStateMachine(outcomes=["finished"])
        _sm.userdata.x = self.start
        with _sm:
            OperatableStateMachine.add(
                "Sub",
                self.use_behavior(Sub, "Sub"),
                transitions={"done": "finished"},
                autonomy={"done": Autonomy.Inherit},
            )
        return _sm


def test_behavior_parameters_and_sub_behaviours(run):
    top = Top()
    assert top.set_parameter("start", "4")
    assert top.set_parameter("Sub/factor", "3")
    assert top.set_parameter("verbose", "true")
    assert not top.set_parameter("nonsense", "1")
    assert top.start == 4.0 and top.contains["Sub"].factor == 3 and top.verbose is True
    sm = top.prepare_for_execution()
    sm.confirm(top.name)
    assert sm.spin() == "finished"
    assert sm._userdata["y"] == 12.0  # the parent's x (4), not the sub-behaviour's default (100)


def test_python2_indentation_reads_tabs_as_python_2():
    from omtp_drake.ros.run.py2 import python2_indentation

    # Line 6 is the course's habit: tab, tab, space, tab (column 24 in Python 2, as line 5).
    source = (
        'def f(y):\n\tif y:\n\t\tif y:\n\t\t\ty += 1\n\t\t\ty += 1\n\t\t \ty += 1\n\treturn y, """a\n\tb"""\n'
    )
    with pytest.raises(TabError):
        compile(source, "f.py", "exec")
    converted = python2_indentation(source)
    namespace: dict = {}
    exec(compile(converted, "f.py", "exec"), namespace)
    assert namespace["f"](1) == (4, "a\n\tb")  # all three in the inner block; the string keeps its tab
    assert converted.splitlines()[5] == " " * 24 + "y += 1"
