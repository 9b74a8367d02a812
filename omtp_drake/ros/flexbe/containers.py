"""FlexBE's ConcurrencyContainer and PriorityContainer.

A :class:`ConcurrencyContainer` runs all its states side by side, each at its
own rate; its ``conditions`` list ``(outcome, [(label, state_outcome), ...])``
pairs, and the first whose states have all returned those outcomes ends the
container with that outcome (the states still running are exited). A state that
returned an outcome waits for the others.

A :class:`PriorityContainer` is a state machine that, while active, runs alone:
the states of a concurrency container outside its path are skipped.
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.ros.flexbe.context import current_run
from omtp_drake.ros.flexbe.engine import OperatableStateMachine, State
from omtp_drake.ros.flexbe.userdata import UserData


def _on_path(path: str, active: Optional[str]) -> bool:
    """Whether ``path`` lies on the active priority container's path (or none is active)."""
    if active is None:
        return True
    return all(a == s for a, s in zip(active.split("/"), path.split("/")))


class ConcurrencyContainer(OperatableStateMachine):
    """FlexBE's ConcurrencyContainer (see the module doc)."""

    def __init__(self, conditions: Any = (), *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._conditions = [(outcome, list(pairs)) for outcome, pairs in (conditions or [])]
        self._returned: dict[str, Optional[str]] = {}
        self._entries: dict[str, Any] = {}

    @property
    def sleep_duration(self) -> float:
        waits = [s.sleep_duration for s in self._running() if s.sleep_duration > 0]
        return min(waits) if waits else 0.0

    def _running(self) -> list[State]:
        return [s for s in self._states if self._returned.get(s.name or "") is None]

    def sleep(self) -> None:
        run = current_run()
        wait = self.sleep_duration
        run.clock.advance_to(run.time + (wait if wait > 0 else self._flexbe_period))

    def _execute_current_state(self) -> Optional[str]:
        run = current_run()
        for state in self._running():
            if not _on_path(state.path, run.priority_path):
                continue  # a priority container elsewhere runs alone
            if state.sleep_duration > 0:
                continue  # not this state's tick yet
            label = state.name or ""
            if label not in self._entries:
                self._entries[label] = run.enter(state.path)
            outcome = self._run_state(state)
            self._returned[label] = outcome
            if outcome is not None:
                self._entries[label].outcome, self._entries[label].left = outcome, run.time
            if state.sleep_duration <= 0:
                state._flexbe_count_tick()  # its period is up: the next one starts
        outcome = self._matching_condition()
        if outcome is None:
            return None
        self._exit_running()
        self._returned, self._entries = {}, {}
        self._current = None
        return outcome

    def _matching_condition(self) -> Optional[str]:
        for outcome, pairs in self._conditions:
            if all(self._returned.get(label) == state_outcome for label, state_outcome in pairs):
                return outcome
        return None

    def _exit_running(self) -> None:
        run = current_run()
        for state in self._running():
            label = state.name or ""
            if label not in self._entries:
                continue  # never started
            with self._view(state) as view:
                if isinstance(state, OperatableStateMachine):
                    state.on_exit(view)
                elif hasattr(state, "_flexbe_leave"):
                    state._flexbe_leave(view)
            self._entries[label].left = run.time

    def execute(self, userdata: Optional[UserData] = None) -> Optional[str]:
        if self._current is None:
            self.assert_consistent_transitions()
            self._current = self.initial_state  # marks the container active
            self._userdata = userdata if userdata is not None else UserData()
            self._userdata.add_from(self._own_userdata)
        return self._execute_current_state()

    def on_exit(self, userdata: UserData) -> None:
        self._exit_running()
        self._returned, self._entries = {}, {}
        self._current = None


class PriorityContainer(OperatableStateMachine):
    """FlexBE's PriorityContainer: while it runs, it runs alone."""

    def __init__(self, conditions: Any = None, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._outer_priority: Optional[str] = None

    def execute(self, userdata: Optional[UserData] = None) -> Optional[str]:
        run = current_run()
        if not (run.priority_path and run.priority_path.startswith(self.path)):
            self._outer_priority = run.priority_path
            run.priority_path = self.path
        outcome = super().execute(userdata)
        if outcome is not None:
            run.priority_path = self._outer_priority
        return outcome
