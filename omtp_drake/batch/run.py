"""Batch evaluation: a scenario's task over seeds and settings, on Dask.

Every (seed, setting) pair is one independent run of
:func:`omtp_drake.tasks.run_task`. Runs go to the workers of a
``dask.distributed`` cluster: by default a :class:`distributed.LocalCluster` of
worker processes on this machine (one thread each), or an existing cluster
given by its scheduler's address (``dask scheduler`` / ``dask worker``)::

    from omtp_drake.batch.run import run_batch, summarize, format_summary

    records = run_batch("lecture6_assignment4", range(20), parts=1,
                        settings={"task.max_tool_speed": [0.6, 1.0]}, out="batch_a4")
    summary_text = format_summary(summarize(records))   # one block per setting

Settings are dotted paths into the :class:`~omtp_drake.scenario.Scenario`
dataclasses (``task.max_tool_speed``, ``spawner.yaw_variance``); a list of
named items is indexed by name (``cameras.logical_camera_2.position_noise_sigma``).
Each value goes through the scenario loader (:func:`scenario_from_dict`), so it
is checked like a value in a scenario file; every bad key, value or seed range
is one error before any cluster starts.

Fault tolerance: a worker never runs a simulation itself. Each worker thread
owns a *runner* subprocess (started once, with omtp_drake imported) that forks
one child per run, so a run that raises, hangs past ``timeout`` (the runner
kills it) or dies of a signal (a segfault in Drake, ``os.abort()``) costs only
its child: it becomes a :class:`RunRecord` of status ``error``, ``timeout`` or
``crashed`` with its message, is retried once on another worker, and the batch
goes on. A child per run also means no state carries over between runs: a run's
result depends only on its scenario and seed.

Outputs in ``out``: ``runs/<run id>.json`` per run (resuming with the same
``out`` skips runs whose JSON exists), ``runs.csv``, ``summary.json``,
``success_rate.png`` and ``cycle_times.png``.
"""

from __future__ import annotations

import collections
import copy
import csv
import dataclasses
import hashlib
import itertools
import json
import logging
import math
import os
import pickle
import re
import select
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
import typing
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, Optional, Union

import numpy as np
import yaml

from omtp_drake.errors import ConfigError, OmtpError, check_duration

# pydrake, dask and matplotlib are imported where used: importing this module
# stays cheap (the ``omtp-drake batch`` command is registered in omtp_drake.cli).
if TYPE_CHECKING:
    from distributed import Client, Future
    from matplotlib.figure import Figure

    from omtp_drake.scenario import Scenario
    from omtp_drake.tasks.run import TaskResult

_log = logging.getLogger(__name__)

#: A run's function: (the prepared scenario, the duration or None) -> its result.
#: The default is :func:`simulate`; tests inject faulty ones (see ``run_batch``).
RunFunction = Callable[["Scenario", Optional[float]], "TaskResult"]

#: Statuses of a run: it ran to its end (successful or not), it raised, it
#: exceeded its wall-time limit, or its process died.
FINISHED, ERROR, TIMEOUT, CRASHED = "finished", "error", "timeout", "crashed"

#: Fields a sweep may not set: identity, and the seed (``seeds`` sets it).
_NOT_SWEEPABLE = ("name", "description", "base", "seed")

#: z of the two-sided 95 % interval.
_Z95 = 1.959963984540054

#: Seconds to connect to a scheduler and to wait for its first worker.
_CONNECT_TIMEOUT_S = 10.0
_WORKERS_TIMEOUT_S = 30.0
#: Seconds a runner may take to start (import omtp_drake) on a loaded machine.
_RUNNER_START_TIMEOUT_S = 300.0
#: Extra seconds the worker waits for its runner after a run's timeout.
_RUNNER_GUARD_S = 30.0


# ----------------------------------------------------------------------------
# Seeds and settings: parsing and checking (no side effects)


def parse_seeds(text: str) -> list[int]:
    """``START:STOP`` (START, ..., STOP - 1, as Python's range) or a comma list
    (``3,7,9``) of seeds >= 0. ConfigError for an empty or malformed range."""
    valid = "valid: START:STOP with integers 0 <= START < STOP (e.g. 0:100), or a list like 3,7,9"
    text = str(text).strip()
    try:
        if ":" in text:
            start_text, stop_text = text.split(":")
            start, stop = int(start_text), int(stop_text)
        else:
            seeds = [int(s) for s in text.split(",")]
    except ValueError:
        raise ConfigError(f"--seeds {text!r} is malformed; {valid}") from None
    if ":" in text:
        if start < 0 or stop <= start:
            raise ConfigError(f"--seeds {text!r} is an empty range; {valid}")
        return list(range(start, stop))
    return check_seeds(seeds)


def check_seeds(seeds: Iterable[int]) -> list[int]:
    """The seeds as a list: at least one, each an integer >= 0, none repeated."""
    out = list(seeds)
    if not out:
        raise ConfigError("seeds: the list of seeds is empty; valid: one or more integers >= 0")
    for seed in out:
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ConfigError(f"seed {seed!r} is invalid; valid: integers >= 0")
    repeated = sorted({s for s in out if out.count(s) > 1})
    if repeated:
        raise ConfigError(f"seeds repeat: {', '.join(map(str, repeated))}; give each seed once")
    return [int(s) for s in out]


def parse_sets(items: Sequence[str]) -> dict[str, list[Any]]:
    """``--set key=v1,v2`` options as {key: [values]} (values parsed as YAML;
    commas inside ``[...]`` do not split)."""
    sweep: dict[str, list[Any]] = {}
    for item in items:
        key, sep, values_text = item.partition("=")
        key = key.strip()
        if not sep or not key or not values_text.strip():
            raise ConfigError(
                f"--set takes KEY=VALUE[,VALUE...] (e.g. task.max_tool_speed=0.6,0.8), got {item!r}"
            )
        if key in sweep:
            raise ConfigError(f"--set {key} is given twice; give its values once: {key}=V1,V2")
        sweep[key] = [_parse_value(key, text) for text in _split_values(values_text)]
    return sweep


def _split_values(text: str) -> list[str]:
    """``a,[1,2],b`` -> ``a``, ``[1,2]``, ``b``."""
    parts, depth, current = [], 0, ""
    for c in text:
        depth += c in "[{"
        depth -= c in "]}"
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    return parts + [current]


def _parse_value(key: str, text: str) -> Any:
    if not text.strip():
        raise ConfigError(f"--set {key}: an empty value; give values like {key}=0.5,1.0")
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise ConfigError(f"--set {key}={text}: not a YAML value ({str(e).splitlines()[0]})") from None
    if isinstance(value, dict) or value is None:
        raise ConfigError(f"--set {key}={text}: not a value; valid: a number, true/false, a string or a list")
    return value


def format_value(value: Any) -> str:
    """A setting's value as text (as it would be written in YAML)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(format_value(v) for v in value) + "]"
    return str(value)


def settings_label(settings: Mapping[str, Any]) -> str:
    """``task.max_tool_speed=0.6 spawner.yaw_variance=0``, or ``defaults``."""
    return " ".join(f"{k}={format_value(v)}" for k, v in settings.items()) or "defaults"


def _unwrap_optional(schema: Any) -> Any:
    if typing.get_origin(schema) is Union:
        options = [a for a in typing.get_args(schema) if a is not type(None)]
        return options[0] if len(options) == 1 else schema
    return schema


def _key_steps(raw: Mapping[str, Any], key: str, scenario: str) -> list[tuple[str, str]]:
    """The steps (``field`` name or list ``item`` name) of ``key`` into a
    scenario's plain data; ConfigError naming the valid keys or names."""
    from omtp_drake.scenario import Scenario, closest_name, is_record, schema_fields

    words = key.split(".")
    if not all(words):
        raise ConfigError(f"--set {key}: malformed key; valid: dotted field names like task.max_tool_speed")
    schema: Any = Scenario
    node: Any = raw
    steps: list[tuple[str, str]] = []
    i = 0
    while True:
        where = ".".join(words[:i]) or "the scenario"
        fields = [f for f in schema_fields(schema) if not (schema is Scenario and f in _NOT_SWEEPABLE)]
        word = words[i]
        if word not in fields:
            near = closest_name(word, fields)
            hint = f" (closest: {near})" if near else ""
            extra = "; set seeds with --seeds" if schema is Scenario and word == "seed" else ""
            raise ConfigError(
                f"--set {key}: unknown key {word!r} in {where}{hint}; valid keys: {', '.join(fields)}{extra}"
            )
        ftype = _unwrap_optional(schema_fields(schema)[word])
        steps.append(("field", word))
        prefix = ".".join(words[: i + 1])
        child = node.get(word) if isinstance(node, dict) else None
        i += 1
        item_type = typing.get_args(ftype)[0] if typing.get_origin(ftype) is list else None
        if item_type is not None and is_record(item_type):
            names = [str(x.get("name")) for x in (child or []) if isinstance(x, dict)]
            if i == len(words):
                raise ConfigError(
                    f"--set {key}: {prefix} is a list of named items; give {prefix}.NAME.FIELD; "
                    f"names: {', '.join(names) or 'none'}"
                )
            name = words[i]
            if name not in names:
                near = closest_name(name, names)
                hint = f" (closest: {near})" if near else ""
                raise ConfigError(
                    f"--set {key}: {scenario} has no {prefix} item {name!r}{hint}; "
                    f"names: {', '.join(names) or 'none'}"
                )
            steps.append(("item", name))
            node = next(x for x in (child or []) if x.get("name") == name)
            schema = item_type
            i += 1
            if i == len(words):
                raise ConfigError(
                    f"--set {key}: names an item, not a value; valid keys under it: "
                    f"{', '.join(schema_fields(item_type))}"
                )
            continue
        if is_record(ftype):
            if child is None:
                raise ConfigError(f"--set {key}: scenario {scenario} has no {prefix} to change")
            if i == len(words):
                raise ConfigError(
                    f"--set {key}: names a group, not a value; valid keys under it: "
                    f"{', '.join(schema_fields(ftype))}"
                )
            node, schema = child, ftype
            continue
        if i != len(words):
            raise ConfigError(f"--set {key}: {prefix} is a value, not a group of keys")
        return steps


def _with_value(raw: dict, steps: list[tuple[str, str]], value: Any) -> dict:
    """A deep copy of ``raw`` with the value at ``steps`` replaced."""
    out = copy.deepcopy(raw)
    node: Any = out
    for kind, name in steps[:-1]:
        node = node[name] if kind == "field" else next(x for x in node if x.get("name") == name)
    node[steps[-1][1]] = copy.deepcopy(value)
    return out


# ----------------------------------------------------------------------------
# The plan: every run, checked, before anything starts


@dataclass(frozen=True)
class RunSpec:
    """One run of a batch: a seed and a setting (values by dotted key)."""

    seed: int
    settings: dict[str, Any]
    #: The prepared scenario of the run's setting (parts and settings applied)
    #: in Drake YAML, shared by the setting's runs: what a worker runs
    #: (pydrake's config classes do not pickle). Its seed is replaced by ``seed``.
    scenario_yaml: str

    def scenario(self) -> Scenario:
        """The run's scenario: setting, parts and seed applied, checked."""
        return dataclasses.replace(scenario_from_yaml(self.scenario_yaml), seed=self.seed)

    @property
    def run_id(self) -> str:
        """A file-name-safe name: ``seed7__task.max_tool_speed=0.6``."""
        text = f"seed{self.seed}" + "".join(f"__{k}={format_value(v)}" for k, v in self.settings.items())
        text = re.sub(r"[^A-Za-z0-9._=+-]", "_", text)
        if len(text) > 150:
            digest = hashlib.sha1(text.encode()).hexdigest()[:12]
            text = f"seed{self.seed}__{digest}"
        return text


@dataclass(frozen=True)
class BatchPlan:
    """Every run of a batch, checked (see :func:`plan_batch`)."""

    scenario: str
    runs: list[RunSpec]
    parts: Optional[int]
    duration: Optional[float]
    #: Identifies the base scenario and run options (for resuming).
    fingerprint: str


def plan_batch(
    scenario: Union[Scenario, str, Path],
    seeds: Union[str, Iterable[int]],
    *,
    settings: Optional[Mapping[str, Sequence[Any]]] = None,
    parts: Optional[int] = None,
    duration: Optional[float] = None,
) -> BatchPlan:
    """Every (setting, seed) run of a batch, each scenario built and checked.

    ``settings`` maps dotted keys to the values to sweep (the grid is every
    combination); ``seeds`` is a list or a ``START:STOP`` string. Raises
    ConfigError / ScenarioError / UnknownNameError for a bad scenario, key,
    value, combination, seed range, ``parts`` or ``duration``; has no side effects.
    """
    from pydrake.common.yaml import yaml_dump_typed

    from omtp_drake.scenario import Scenario, load_scenario

    seed_list = parse_seeds(seeds) if isinstance(seeds, str) else check_seeds(seeds)
    base = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    base.required_task()
    if duration is not None:
        check_duration("--duration", duration)
    sweep = {str(k): list(v) for k, v in (settings or {}).items()}
    if parts is not None and "task.parts" in sweep:
        raise ConfigError("give the number of parts once: --parts or --set task.parts, not both")
    base_text = yaml_dump_typed(base)
    raw = yaml.safe_load(base_text)
    steps = {}
    for key, values in sweep.items():
        if not values:
            raise ConfigError(f"--set {key}: no values; give values like {key}=0.5,1.0")
        steps[key] = _key_steps(raw, key, base.name)
        texts = [format_value(v) for v in values]
        repeated = sorted({t for t in texts if texts.count(t) > 1})
        if repeated:
            raise ConfigError(f"--set {key}: value {repeated[0]} is given twice")
        for value in values:  # each value alone: its error names it
            _build(raw, {key: value}, steps, base.name, parts)
    runs: list[RunSpec] = []
    for combo in itertools.product(*sweep.values()):
        setting = dict(zip(sweep, combo))
        text = yaml_dump_typed(_build(raw, setting, steps, base.name, parts))
        runs += [RunSpec(seed=seed, settings=setting, scenario_yaml=text) for seed in seed_list]
    fingerprint = hashlib.sha1(f"{base_text}\nparts={parts}\nduration={duration}".encode()).hexdigest()
    return BatchPlan(scenario=base.name, runs=runs, parts=parts, duration=duration, fingerprint=fingerprint)


def _build(
    raw: dict, setting: Mapping[str, Any], steps: Mapping[str, list], name: str, parts: Optional[int]
) -> Scenario:
    """The scenario with ``setting`` applied, loaded and prepared (checked)."""
    from omtp_drake.scenario import scenario_from_dict
    from omtp_drake.tasks.run import prepare

    data = raw
    for key, value in setting.items():
        data = _with_value(data, steps[key], value)
    source = "--set " + ", ".join(f"{k}={format_value(v)}" for k, v in setting.items())
    try:
        return prepare(scenario_from_dict(data, source=source, name=name), parts=parts)
    except OmtpError as e:
        text = str(e)
        raise ConfigError(text if text.startswith(source) or not setting else f"{source}: {text}") from None


def scenario_from_yaml(text: str) -> Scenario:
    """A scenario from its Drake YAML (``RunSpec.scenario_yaml``), checked."""
    from pydrake.common.yaml import yaml_load_typed

    from omtp_drake.scenario import Scenario

    scenario = yaml_load_typed(schema=Scenario, data=text, defaults=Scenario())
    scenario.validate()
    return scenario


# ----------------------------------------------------------------------------
# Records


@dataclass
class RunRecord:
    """The outcome of one run of a batch (``to_dict`` is its JSON file)."""

    scenario: str
    seed: int
    settings: dict[str, Any]
    #: ``finished`` (ran to its end, successful or not), ``error``, ``timeout`` or ``crashed``.
    status: str
    #: What went wrong (empty when finished).
    message: str = ""
    #: The task's result (None unless finished).
    result: Optional[TaskResult] = None
    #: Attempts made (a failed attempt is retried once, on another worker).
    attempts: int = 1
    #: Address of the worker of the last attempt.
    worker: str = ""
    #: Wall seconds of the last attempt in its process (building included).
    run_wall_time_s: float = math.nan
    #: Earlier attempts that failed: status, message, worker.
    failed_attempts: list[dict[str, Any]] = field(default_factory=list)

    @property
    def success(self) -> bool:
        """Finished and judged successful."""
        return self.status == FINISHED and self.result is not None and self.result.success

    @property
    def run_id(self) -> str:
        return RunSpec(self.seed, self.settings, "").run_id

    @property
    def ledger_anomaly(self) -> bool:
        """Finished with parts unaccounted for (``TaskResult.accounted_for``): the ledger
        does not balance, or a part is left loose that the controller did not give up
        on with a record of where it lies."""
        return self.result is not None and not self.result.accounted_for

    @property
    def failure_reason(self) -> str:
        """Why the run did not succeed (empty when it did): its status if it did
        not finish, else its last failed pick's reason, else ``incomplete``."""
        if self.success:
            return ""
        if self.status != FINISHED or self.result is None:
            return self.status
        failed = [p.reason for p in self.result.picks if not p.success]
        return failed[-1] if failed else "incomplete"

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"scenario": self.scenario, "seed": self.seed}
        if self.result is not None:
            out.update(self.result.to_dict())
            out["bin"] = self.result.bin
        out.update(
            {
                "settings": dict(self.settings),
                "status": self.status,
                "message": self.message,
                "attempts": self.attempts,
                "worker": self.worker,
                "run_wall_time_s": self.run_wall_time_s,
                "failed_attempts": list(self.failed_attempts),
            }
        )
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> RunRecord:
        """The record of ``to_dict`` (a run's JSON file)."""
        from omtp_drake.tasks.run import TaskResult

        result = TaskResult.from_dict(data, data["bin"]) if "summary" in data else None
        return cls(
            scenario=data["scenario"],
            seed=data["seed"],
            settings=dict(data["settings"]),
            status=data["status"],
            message=data.get("message", ""),
            result=result,
            attempts=data.get("attempts", 1),
            worker=data.get("worker", ""),
            run_wall_time_s=data.get("run_wall_time_s", math.nan),
            failed_attempts=list(data.get("failed_attempts", [])),
        )


# ----------------------------------------------------------------------------
# Isolation: a runner subprocess per worker thread, a forked child per run


def _write_frame(fd: int, obj: Any) -> None:
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    view = memoryview(struct.pack("!Q", len(data)) + data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exact(fd: int, n: int, deadline: Optional[float]) -> bytes:
    chunks, left = [], n
    while left:
        if deadline is not None:
            wait = deadline - time.monotonic()
            if wait <= 0 or not select.select([fd], [], [], wait)[0]:
                raise TimeoutError("no answer in time")
        chunk = os.read(fd, min(left, 1 << 20))
        if not chunk:
            raise EOFError("the pipe closed")
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def _read_frame(fd: int, deadline: Optional[float] = None) -> Any:
    (n,) = struct.unpack("!Q", _read_exact(fd, 8, deadline))
    return pickle.loads(_read_exact(fd, n, deadline))


def _runner_main() -> None:
    """The runner subprocess: reads runs from stdin, forks a child for each,
    enforces its timeout, answers on stdout (see :class:`_Sandbox`)."""
    in_fd, out_fd = os.dup(0), os.dup(1)
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    os.dup2(2, 1)  # stray prints go to stderr, not into the protocol
    hello = _read_frame(in_fd)
    sys.path[:] = hello["sys_path"]
    # Preloaded once: every forked child starts with pydrake and omtp_drake imported.
    import pydrake.common  # noqa: F401

    import omtp_drake.tasks.run  # noqa: F401

    logging.getLogger("drake").setLevel(logging.ERROR)
    _write_frame(out_fd, {"ready": os.getpid()})
    while True:
        try:
            request = _read_frame(in_fd)
        except EOFError:
            return
        _write_frame(out_fd, _fork_and_run(request["payload"], request["timeout"], in_fd))


def _fork_and_run(payload: bytes, timeout: Optional[float], watch_fd: int) -> dict[str, Any]:
    """Runs the pickled (function, args) in a forked child; kills it at the
    timeout, or (and exits) when ``watch_fd`` closes (the worker is gone)."""
    with tempfile.TemporaryFile() as err:
        r, w = os.pipe()
        start = time.monotonic()
        pid = os.fork()
        if pid == 0:
            _child(payload, r, w, err.fileno())
        os.close(w)
        chunks: list[bytes] = []
        timed_out = False
        deadline = None if timeout is None else start + timeout
        while True:
            wait = None if deadline is None else max(0.0, deadline - time.monotonic())
            ready = select.select([r, watch_fd], [], [], wait)[0]
            if not ready:
                timed_out = True
                os.kill(pid, signal.SIGKILL)
                break
            if watch_fd in ready:  # the worker never writes while waiting: it is gone
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                os._exit(0)
            chunk = os.read(r, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
        os.close(r)
        _, status = os.waitpid(pid, 0)
        wall = time.monotonic() - start
        if timed_out:
            return {"status": TIMEOUT, "message": f"exceeded the timeout of {timeout:g} s wall (killed)"}
        try:
            reply = pickle.loads(b"".join(chunks))
            reply["wall"] = wall
            return reply
        except Exception:  # no complete answer: the child died
            if os.WIFSIGNALED(status):
                sig = os.WTERMSIG(status)
                name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
                what = f"the run's process died of {name}"
            else:
                what = f"the run's process exited with code {os.waitstatus_to_exitcode(status)}"
            tail = _tail(err)
            return {"status": CRASHED, "message": what + (f"; its last output: {tail}" if tail else "")}


def _tail(f: Any, limit: int = 600) -> str:
    """The last lines of a file (a child's stderr), as one line."""
    f.seek(0, os.SEEK_END)
    size = f.tell()
    f.seek(max(0, size - limit))
    lines = [ln.strip() for ln in f.read().decode(errors="replace").splitlines() if ln.strip()]
    return " | ".join(lines[-4:])


def _child(payload: bytes, r: int, w: int, err_fd: int) -> NoReturn:
    """The forked child of one run: never returns."""
    code = 0
    try:
        os.close(r)
        os.dup2(err_fd, 2)
        os.dup2(err_fd, 1)
        try:
            fn, args = pickle.loads(payload)
            reply: dict[str, Any] = {"status": FINISHED, "value": pickle.dumps(fn(*args)), "message": ""}
        except BaseException as e:  # every failure of a run is recorded, whatever it is
            reply = {"status": ERROR, "value": None, "message": describe_exception(e)}
        data = memoryview(pickle.dumps(reply))
        while data:
            data = data[os.write(w, data) :]
    except BaseException:
        code = 1
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:
                pass
        os._exit(code)


def describe_exception(e: BaseException) -> str:
    """``Type: message (at file:line in function)``, on one line."""
    text = " ".join(str(e).split())
    where = ""
    tb = e.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    if tb is not None:
        code = tb.tb_frame.f_code
        where = f" (at {Path(code.co_filename).name}:{tb.tb_lineno} in {code.co_name})"
    return f"{type(e).__name__}: {text[:500]}{where}"


class _Sandbox:
    """A runner subprocess (started on first use, restarted if it dies) that runs
    each call in a forked child: a crash or hang costs the child, not the worker."""

    def __init__(self) -> None:
        self._proc: Optional[subprocess.Popen] = None

    def _start(self) -> subprocess.Popen:
        env = dict(os.environ)
        for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            env.setdefault(var, "1")  # one core per run: the workers are the parallelism
        proc = subprocess.Popen(
            [sys.executable, "-c", "from omtp_drake.batch.run import _runner_main; _runner_main()"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            bufsize=0,
            env=env,
        )
        assert proc.stdin is not None and proc.stdout is not None
        try:
            _write_frame(proc.stdin.fileno(), {"sys_path": list(sys.path)})
            _read_frame(proc.stdout.fileno(), time.monotonic() + _RUNNER_START_TIMEOUT_S)
        except (EOFError, OSError, TimeoutError) as e:
            proc.kill()
            proc.wait()
            raise RuntimeError(f"the run sandbox did not start ({e})") from None
        return proc

    def stop(self) -> None:
        if self._proc is not None:
            self._proc.kill()
            self._proc.wait()
            self._proc = None

    def call(self, fn: Callable[..., Any], args: tuple, timeout: Optional[float]) -> dict[str, Any]:
        """{status, message, value (the pickled return value), wall} of ``fn(*args)``."""
        import cloudpickle

        payload = cloudpickle.dumps((fn, args))  # by value for notebook functions
        if self._proc is None or self._proc.poll() is not None:
            self._proc = self._start()
        proc = self._proc
        assert proc.stdin is not None and proc.stdout is not None
        deadline = None if timeout is None else time.monotonic() + timeout + _RUNNER_GUARD_S
        try:
            _write_frame(proc.stdin.fileno(), {"payload": payload, "timeout": timeout})
            return _read_frame(proc.stdout.fileno(), deadline)
        except (EOFError, OSError, TimeoutError) as e:
            self.stop()
            return {"status": CRASHED, "message": f"the run sandbox died ({e})"}


_SANDBOXES = threading.local()


def _sandbox() -> _Sandbox:
    """This thread's sandbox."""
    if not hasattr(_SANDBOXES, "sandbox"):
        _SANDBOXES.sandbox = _Sandbox()
    return _SANDBOXES.sandbox


# ----------------------------------------------------------------------------
# Running on Dask


def simulate(scenario: Scenario, duration: Optional[float]) -> TaskResult:
    """The default run function: the scenario's task (:func:`run_task`)."""
    from omtp_drake.tasks.run import run_task

    return run_task(scenario, duration=duration)


def _run_in_child(spec: RunSpec, duration: Optional[float], run_fn: RunFunction) -> TaskResult:
    return run_fn(spec.scenario(), duration)


@dataclass(frozen=True)
class _Job:
    """What a worker needs for one run."""

    scenario: str
    spec: RunSpec
    duration: Optional[float]
    timeout: Optional[float]
    run_fn: RunFunction


def _worker_address() -> str:
    try:
        from distributed import get_worker

        return str(get_worker().address)
    except (ImportError, ValueError):
        return ""


def _execute(job: _Job) -> RunRecord:
    """A Dask task: one run in this worker's sandbox."""
    from omtp_drake.tasks.run import TaskResult

    outcome = _sandbox().call(_run_in_child, (job.spec, job.duration, job.run_fn), job.timeout)
    status = outcome["status"]
    result = None
    message = outcome.get("message", "")
    if status == FINISHED:
        try:
            result = pickle.loads(outcome["value"])
        except Exception as e:
            status, message = ERROR, f"the run's result could not be read: {describe_exception(e)}"
        if result is not None and not isinstance(result, TaskResult):
            status, message = ERROR, f"the run function returned {type(result).__name__}, not a TaskResult"
            result = None
    return RunRecord(
        scenario=job.scenario,
        seed=job.spec.seed,
        settings=dict(job.spec.settings),
        status=status,
        message=message,
        result=result,
        worker=_worker_address(),
        run_wall_time_s=float(outcome.get("wall", math.nan)),
    )


def _versions() -> dict[str, str]:
    """Versions a worker must share with the client."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for package in ("omtp_drake", "drake"):
        try:
            out[package] = version(package)
        except PackageNotFoundError:
            out[package] = "missing"
    return out


def default_workers() -> int:
    """Worker processes of a local cluster by default: the cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


@contextmanager
def connect(workers: Optional[int] = None, scheduler: Optional[str] = None) -> Iterator[Client]:
    """A Dask client: on a new LocalCluster of ``workers`` processes (one thread
    each, no dashboard; default: the core count) or on the cluster whose
    scheduler is at ``scheduler``. Closed (and the local cluster stopped) on exit."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout=_CONNECT_TIMEOUT_S)
        except (OSError, TimeoutError, ValueError) as e:
            raise ConfigError(
                f"--scheduler {scheduler!r}: cannot connect ({e}); start one with `dask scheduler` "
                "and give its address, e.g. tcp://10.0.0.5:8786"
            ) from None
        try:
            _check_cluster(client, scheduler)
            yield client
        finally:
            client.close()
        return
    n = default_workers() if workers is None else workers
    with (
        _quiet_logger("distributed", logging.ERROR),
        LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client


@contextmanager
def _quiet_logger(name: str, level: int) -> Iterator[None]:
    """The logger ``name`` at ``level`` at least (a local cluster's scheduler
    logs in this process; its INFO lines would reach the CLI's handler)."""
    logger = logging.getLogger(name)
    old = logger.level
    logger.setLevel(max(level, logger.getEffectiveLevel()))
    try:
        yield
    finally:
        logger.setLevel(old)


def _check_cluster(client: Client, scheduler: str) -> None:
    try:
        client.wait_for_workers(1, timeout=_WORKERS_TIMEOUT_S)
    except (TimeoutError, OSError):
        raise ConfigError(
            f"--scheduler {scheduler!r} has no workers after {_WORKERS_TIMEOUT_S:g} s; "
            f"start some with `dask worker {scheduler} --nthreads 1`"
        ) from None
    local = _versions()
    try:
        remote = client.run(_versions)
    except Exception as e:  # a worker that cannot import omtp_drake fails here
        raise ConfigError(
            f"--scheduler {scheduler!r}: a worker cannot run omtp_drake ({describe_exception(e)}); "
            "install the same omtp_drake and drake on every worker"
        ) from None
    bad = {w: v for w, v in remote.items() if v != local}
    if bad:
        listed = "; ".join(f"{w}: {v}" for w, v in sorted(bad.items()))
        raise ConfigError(f"workers run other versions than this client ({local}): {listed}")


def _record_of(future: Future, job: _Job) -> RunRecord:
    """The record a finished future holds, or one for the failure of its task."""
    from distributed import KilledWorker

    if future.status == "finished":
        return future.result()
    try:
        exc = future.exception()
    except Exception as e:  # cancelled (e.g. the scheduler lost it): the reason is the error
        exc = e
    # KilledWorker: the task's worker died each time it ran it (e.g. out of memory).
    status = CRASHED if isinstance(exc, KilledWorker) else ERROR
    return RunRecord(
        scenario=job.scenario,
        seed=job.spec.seed,
        settings=dict(job.spec.settings),
        status=status,
        message=describe_exception(exc) if exc is not None else f"the task ended as {future.status}",
    )


def _run_jobs(
    client: Client, jobs: Sequence[_Job], retries: int, on_record: Callable[[RunRecord], None]
) -> None:
    """Submits every job; a failed attempt is submitted again (at most
    ``retries`` times) to the other workers; ``on_record`` gets each final record."""
    from distributed import as_completed

    pending = as_completed()
    meta: dict[str, tuple[_Job, int, list[dict[str, Any]]]] = {}

    def submit(job: _Job, attempt: int, failures: list[dict[str, Any]], avoid: str) -> None:
        workers = None
        if avoid:
            others = [w for w in client.has_what() if w != avoid]
            workers = others or None
        key = f"omtp-run-{job.spec.run_id}-{attempt}-{uuid.uuid4().hex[:8]}"
        # Only the other workers (a loose restriction would let an idle
        # worker steal the task back); any worker when there is no other.
        future = client.submit(_execute, job, key=key, pure=False, workers=workers)
        meta[future.key] = (job, attempt, failures)
        pending.add(future)

    for job in jobs:
        submit(job, 1, [], "")
    for future in pending:
        job, attempt, failures = meta.pop(future.key)
        record = _record_of(future, job)
        future.release()
        if record.status != FINISHED and attempt <= retries:
            _log.info("run %s: %s (%s); retrying", job.spec.run_id, record.status, record.message)
            failure = {"status": record.status, "message": record.message, "worker": record.worker}
            submit(job, attempt + 1, failures + [failure], record.worker)
            continue
        record.attempts = attempt
        record.failed_attempts = failures
        on_record(record)


def run_batch(
    scenario: Union[Scenario, str, Path],
    seeds: Union[str, Iterable[int]],
    *,
    settings: Optional[Mapping[str, Sequence[Any]]] = None,
    parts: Optional[int] = None,
    duration: Optional[float] = None,
    workers: Optional[int] = None,
    scheduler: Optional[str] = None,
    client: Optional[Client] = None,
    timeout: Optional[float] = None,
    retries: int = 1,
    out: Optional[Union[str, Path]] = None,
    progress: bool = True,
    run_fn: RunFunction = simulate,
) -> list[RunRecord]:
    """Runs the scenario's task for every (setting, seed) on Dask; the records in
    plan order (setting by setting, seed by seed).

    Where: a new LocalCluster of ``workers`` processes (default: the core count),
    the cluster at ``scheduler`` (``tcp://host:8786``), or your own ``client``
    (give at most one). ``timeout``: wall seconds per run (None: no limit).
    ``retries``: further attempts of a failed run, on another worker if there is one.
    ``out``: the folder of results (see the module doc); runs whose JSON is
    there already are skipped (resume). ``run_fn(scenario, duration) -> TaskResult``
    replaces the simulation (tests inject faults with it; it must be importable
    or picklable by value). Every argument is checked before a cluster starts.
    """
    plan = plan_batch(scenario, seeds, settings=settings, parts=parts, duration=duration)
    if sum(x is not None for x in (workers, scheduler, client)) > 1:
        raise ConfigError("give at most one of workers, scheduler and client")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ConfigError(f"--workers must be an integer >= 1, got {workers!r}")
    if timeout is not None:
        check_duration("--timeout", timeout)
    if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
        raise ConfigError(f"retries must be an integer >= 0, got {retries!r}")
    if not callable(run_fn):
        raise ConfigError(f"run_fn must be a function (scenario, duration) -> TaskResult, got {run_fn!r}")
    store = _Store(Path(out), plan) if out is not None else None
    if store is not None:
        store.check()
    done: dict[str, RunRecord] = store.load_done() if store is not None else {}
    jobs = [_Job(plan.scenario, spec, plan.duration, timeout, run_fn) for spec in _seed_major(plan.runs)]
    jobs = [j for j in jobs if j.spec.run_id not in done]
    if done:
        _log.info("resuming: %d of %d runs already done", len(done), len(plan.runs))
    if jobs:
        with _client_for(workers, scheduler, client) as live:
            if store is not None:
                store.start()
            _run_with_progress(plan, jobs, done, store, live, retries, progress)
    elif store is not None:
        store.start()
    records = [done[spec.run_id] for spec in plan.runs]
    if store is not None:
        store.finish(records)
    return records


@contextmanager
def _client_for(
    workers: Optional[int], scheduler: Optional[str], client: Optional[Client]
) -> Iterator[Client]:
    """The caller's client, or a new one (see :func:`connect`)."""
    if client is not None:
        yield client
    else:
        with connect(workers, scheduler) as own:
            yield own


def _seed_major(runs: Sequence[RunSpec]) -> list[RunSpec]:
    """Seed by seed, every setting: an interrupted batch has all settings in part."""
    return sorted(runs, key=lambda r: r.seed)


def _run_with_progress(
    plan: BatchPlan,
    jobs: Sequence[_Job],
    done: dict[str, RunRecord],
    store: Optional[_Store],
    client: Client,
    retries: int,
    progress: bool,
) -> None:
    from tqdm import tqdm

    succeeded = sum(r.success for r in done.values())
    bar = tqdm(total=len(plan.runs), initial=len(done), desc=plan.scenario, unit="run", disable=not progress)
    bar.set_postfix_str(f"{succeeded}/{len(done)} succeeded")

    def on_record(record: RunRecord) -> None:
        nonlocal succeeded
        done[record.run_id] = record
        if store is not None:
            store.write(record)
        succeeded += record.success
        bar.update(1)
        bar.set_postfix_str(f"{succeeded}/{len(done)} succeeded")
        if record.status != FINISHED:
            _log.warning("run %s: %s: %s", record.run_id, record.status, record.message)

    try:
        _run_jobs(client, jobs, retries, on_record)
    finally:
        bar.close()


# ----------------------------------------------------------------------------
# Results on disk


class _Store:
    """The results folder: ``batch.json`` (what batch it holds), ``runs/*.json``,
    ``runs.csv``, ``summary.json`` and the plots."""

    def __init__(self, out: Path, plan: BatchPlan):
        self.out = out
        self.plan = plan
        self.runs_dir = out / "runs"
        self.manifest = out / "batch.json"

    def _manifest_data(self) -> dict[str, Any]:
        return {
            "scenario": self.plan.scenario,
            "parts": self.plan.parts,
            "duration": self.plan.duration,
            "fingerprint": self.plan.fingerprint,
        }

    def check(self) -> None:
        """ConfigError if ``out`` holds something other than this batch's results."""
        if self.out.exists() and not self.out.is_dir():
            raise ConfigError(f"--out {str(self.out)!r} is a file; give a folder")
        if not self.manifest.is_file():
            return
        try:
            held = json.loads(self.manifest.read_text())
        except (OSError, ValueError) as e:
            raise ConfigError(f"--out {str(self.out)!r}: unreadable {self.manifest.name} ({e})") from None
        if held.get("fingerprint") != self.plan.fingerprint:
            raise ConfigError(
                f"--out {str(self.out)!r} holds a batch of another scenario or options "
                f"({held.get('scenario')}, parts {held.get('parts')}, duration {held.get('duration')}); "
                "give another --out to start a new batch"
            )

    def load_done(self) -> dict[str, RunRecord]:
        """Records of the plan's runs whose JSON exists (unreadable ones are run again)."""
        done = {}
        for spec in self.plan.runs:
            path = self.runs_dir / f"{spec.run_id}.json"
            if not path.is_file():
                continue
            try:
                record = RunRecord.from_dict(json.loads(path.read_text()))
            except (OSError, ValueError, KeyError, TypeError) as e:
                _log.warning("%s is unreadable (%s); running it again", path, e)
                continue
            if record.seed == spec.seed and record.settings == spec.settings:
                done[spec.run_id] = record
        return done

    def start(self) -> None:
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        _write_json(self.manifest, self._manifest_data())

    def write(self, record: RunRecord) -> None:
        _write_json(self.runs_dir / f"{record.run_id}.json", record.to_dict())

    def finish(self, records: Sequence[RunRecord]) -> None:
        write_table(records, self.out / "runs.csv")
        summaries = summarize(records)
        _write_json(self.out / "summary.json", [s.to_dict() for s in summaries])
        plot_success_rates(summaries).savefig(self.out / "success_rate.png", dpi=100)
        plot_cycle_time_histograms(records).savefig(self.out / "cycle_times.png", dpi=100)


def _write_json(path: Path, data: Any) -> None:
    """Written whole or not at all (a killed batch leaves no half file)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2))
    os.replace(tmp, path)


def write_table(records: Sequence[RunRecord], path: Union[str, Path]) -> Path:
    """One CSV row per run: seed, settings, status, success and the summary numbers."""
    keys: list[str] = []
    for r in records:
        keys += [k for k in r.settings if k not in keys]
    columns = ["scenario", "seed", *keys, "status", "success", "attempts", "in_bin", "parts"]
    columns += ["picks", "failed_picks", "failure_reason", "mean_cycle_time_s", "max_cycle_time_s"]
    columns += ["sim_time_s", "wall_time_s", "real_time_factor", "ledger_balanced", "loose_parts"]
    columns += ["run_wall_time_s", "worker", "message"]
    path = Path(path)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for r in records:
            row: dict[str, Any] = {"scenario": r.scenario, "seed": r.seed, "status": r.status}
            row.update({k: format_value(r.settings[k]) if k in r.settings else "" for k in keys})
            row.update(success=r.success, attempts=r.attempts, failure_reason=r.failure_reason)
            row.update(run_wall_time_s=r.run_wall_time_s, worker=r.worker, message=r.message)
            if r.result is not None:
                s = r.result.summary
                row.update(
                    in_bin=s["in_bin"], parts=s["parts"], picks=s["attempted"], failed_picks=s["failed"]
                )
                row.update({k: s[k] for k in ("mean_cycle_time_s", "max_cycle_time_s", "sim_time_s")})
                row.update(wall_time_s=s["wall_time_s"], real_time_factor=s["real_time_factor"])
                row.update(ledger_balanced=r.result.ledger.balanced, loose_parts=r.result.ledger.loose)
            writer.writerow(row)
    return path


# ----------------------------------------------------------------------------
# Summaries and plots


def wilson_interval(successes: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """The Wilson score interval of a success rate (95 % by default); (0, 1) for n = 0."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    lo = 0.0 if successes == 0 else max(0.0, min(p, centre - half))
    hi = 1.0 if successes == n else min(1.0, max(p, centre + half))
    return lo, hi


@dataclass
class SettingSummary:
    """What the runs of one setting add up to."""

    settings: dict[str, Any]
    runs: int
    successes: int
    #: Runs by status (finished, error, timeout, crashed).
    statuses: dict[str, int]
    #: 95 % Wilson interval of the success rate.
    interval: tuple[float, float]
    #: Cycle times (simulated s) of the successful picks.
    cycle_times: list[float]
    #: Failed runs by reason (status, or the last failed pick's reason, or ``incomplete``).
    failure_reasons: dict[str, int]
    #: Failed picks (recovered or not) by reason.
    failed_picks: dict[str, int]
    #: Seeds of finished runs with parts unaccounted for (ledger unbalanced or parts loose).
    ledger_anomalies: list[int]
    #: Mean real-time factor of the finished runs.
    real_time_factor: float

    @property
    def label(self) -> str:
        return settings_label(self.settings)

    @property
    def success_rate(self) -> float:
        return self.successes / self.runs if self.runs else math.nan

    @property
    def cycle_mean(self) -> float:
        return float(np.mean(self.cycle_times)) if self.cycle_times else math.nan

    @property
    def cycle_p95(self) -> float:
        return float(np.percentile(self.cycle_times, 95)) if self.cycle_times else math.nan

    @property
    def cycle_worst(self) -> float:
        return max(self.cycle_times) if self.cycle_times else math.nan

    def to_dict(self) -> dict[str, Any]:
        return {
            "settings": dict(self.settings),
            "runs": self.runs,
            "successes": self.successes,
            "success_rate": self.success_rate,
            "success_rate_95ci": list(self.interval),
            "statuses": dict(self.statuses),
            "cycle_time_mean_s": self.cycle_mean,
            "cycle_time_p95_s": self.cycle_p95,
            "cycle_time_worst_s": self.cycle_worst,
            "failure_reasons": dict(self.failure_reasons),
            "failed_picks": dict(self.failed_picks),
            "ledger_anomalies": list(self.ledger_anomalies),
            "real_time_factor": self.real_time_factor,
        }


def summarize(records: Sequence[RunRecord]) -> list[SettingSummary]:
    """One summary per setting, in the order the settings first appear."""
    groups: dict[str, list[RunRecord]] = {}
    for r in records:
        groups.setdefault(json.dumps(r.settings, sort_keys=False), []).append(r)
    out = []
    for group in groups.values():
        successes = sum(r.success for r in group)
        finished = [r.result for r in group if r.status == FINISHED and r.result is not None]
        rtfs = [x for x in (res.summary["real_time_factor"] for res in finished) if math.isfinite(x)]
        out.append(
            SettingSummary(
                settings=dict(group[0].settings),
                runs=len(group),
                successes=successes,
                statuses=dict(collections.Counter(r.status for r in group)),
                interval=wilson_interval(successes, len(group)),
                cycle_times=[p.cycle_time for res in finished for p in res.picks if p.success and p.part],
                failure_reasons=dict(collections.Counter(r.failure_reason for r in group if not r.success)),
                failed_picks=dict(
                    collections.Counter(p.reason for res in finished for p in res.picks if not p.success)
                ),
                ledger_anomalies=[r.seed for r in group if r.ledger_anomaly],
                real_time_factor=float(np.mean(rtfs)) if rtfs else math.nan,
            )
        )
    return out


def format_summary(summaries: Sequence[SettingSummary]) -> str:
    """The summary as text, a block per setting."""
    lines = []
    for s in summaries:
        lo, hi = s.interval
        lines.append(f"{s.label}:")
        lines.append(
            f"  runs {s.runs}: success {s.successes}/{s.runs} = {100 * s.success_rate:.1f} % "
            f"(95 % CI {100 * lo:.1f}-{100 * hi:.1f} %)"
            + (
                "; " + ", ".join(f"{k} {v}" for k, v in s.statuses.items() if k != FINISHED)
                if set(s.statuses) - {FINISHED}
                else ""
            )
        )
        lines.append(
            f"  cycle time (s, {len(s.cycle_times)} picks): mean {s.cycle_mean:.2f}, "
            f"p95 {s.cycle_p95:.2f}, worst {s.cycle_worst:.2f}; real-time factor {s.real_time_factor:.1f}"
        )
        if s.failure_reasons:
            reasons = ", ".join(
                f"{k} {v}" for k, v in sorted(s.failure_reasons.items(), key=lambda kv: -kv[1])
            )
            lines.append(f"  failed runs by reason: {reasons}")
        if s.failed_picks:
            picks = ", ".join(f"{k} {v}" for k, v in sorted(s.failed_picks.items(), key=lambda kv: -kv[1]))
            lines.append(f"  failed picks by reason: {picks}")
        anomalies = ", ".join(map(str, s.ledger_anomalies)) if s.ledger_anomalies else "none"
        lines.append(
            f"  ledger anomalies (parts unaccounted for): {len(s.ledger_anomalies)} (seeds: {anomalies})"
        )
    return "\n".join(lines)


def plot_success_rates(summaries: Sequence[SettingSummary]) -> Figure:
    """Success rate per setting with its 95 % Wilson interval."""
    from matplotlib.figure import Figure

    if not summaries:
        raise ConfigError("plot_success_rates needs at least one setting's summary")
    fig = Figure(figsize=(max(5.0, 1.2 * len(summaries) + 2), 4.5), layout="constrained")
    ax = fig.subplots()
    x = np.arange(len(summaries))
    rates = np.array([s.success_rate for s in summaries])
    lo = np.array([s.interval[0] for s in summaries])
    hi = np.array([s.interval[1] for s in summaries])
    ax.bar(x, 100 * rates, width=0.6, color="tab:green", alpha=0.7)
    ax.errorbar(
        x,
        100 * rates,
        yerr=100 * np.clip(np.vstack([rates - lo, hi - rates]), 0, None),
        fmt="none",
        ecolor="k",
        capsize=6,
    )
    for xi, s in zip(x, summaries):
        ax.annotate(f"{s.successes}/{s.runs}", (xi, 2), ha="center", fontsize=8)
    ax.set_xticks(x, [s.label.replace(" ", "\n") for s in summaries], fontsize=8)
    ax.set_ylim(0, 105)
    ax.set_ylabel("success rate [%] (95 % Wilson interval)")
    ax.set_title("Success rate per setting")
    return fig


def plot_cycle_time_histograms(records: Sequence[RunRecord]) -> Figure:
    """Histograms of the successful picks' cycle times, one panel per setting."""
    from matplotlib.figure import Figure

    summaries = summarize(records)
    if not summaries:
        raise ConfigError("plot_cycle_time_histograms needs at least one record")
    n = len(summaries)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(4.0 * cols, 3.0 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, sharex=True, squeeze=False)).ravel()
    every = [c for s in summaries for c in s.cycle_times]
    bins = np.histogram_bin_edges(every, bins=20) if every else np.linspace(0, 1, 21)
    for ax, s in zip(axes, summaries):
        if s.cycle_times:
            ax.hist(s.cycle_times, bins=bins, color="tab:blue", alpha=0.8)
        else:
            ax.text(0.5, 0.5, "no successful picks", ha="center", va="center", transform=ax.transAxes)
        ax.set_title(s.label, fontsize=8)
        ax.set_xlabel("cycle time [s]")
        ax.set_ylabel("picks")
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig
