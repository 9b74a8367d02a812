"""Batch evaluation: a scenario's task over seeds and settings, on Dask.

Every (seed, setting) pair is one independent run of
:func:`omtp_drake.tasks.run_task`. Runs go to the workers of a
``dask.distributed`` cluster: by default a :class:`distributed.LocalCluster` of
worker processes on this machine (one thread each), or an existing cluster
given by its scheduler's address (``dask scheduler`` / ``dask worker``)::

    from omtp_drake.batch import run_batch, summarize, format_summary

    records = run_batch("lecture6_assignment4", range(20), parts=1,
                        settings={"task.max_tool_speed": [0.6, 1.0]}, out="batch_a4")
    summary_text = format_summary(summarize(records))   # one block per setting

The plan (every run, checked) comes from :mod:`omtp_drake.batch.sweep`; each run
goes to its worker's sandbox (:mod:`omtp_drake.batch.sandbox`), so a run that
raises, hangs or crashes becomes a :class:`~omtp_drake.batch.run_records.RunRecord` of status ``error``,
``timeout`` or ``crashed``, is retried once on another worker, and the batch
goes on. Results go to ``out`` (:mod:`omtp_drake.batch.store`).
"""

from __future__ import annotations

import logging
import math
import os
import pickle
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Union

from omtp_drake.batch.run_records import CRASHED, ERROR, FINISHED, RunRecord
from omtp_drake.batch.sandbox import RunFunction, run_in_child, simulate, thread_sandbox
from omtp_drake.batch.store import ResultStore
from omtp_drake.batch.sweep import BatchPlan, RunSpec, plan_batch
from omtp_drake.errors import ConfigError, check_duration, describe_exception
from omtp_drake.viz.meshcat import free_meshcats_here

# dask is imported where used: importing this module stays cheap (the
# ``omtp-drake batch`` command is registered in omtp_drake.cli).
if TYPE_CHECKING:
    from distributed import Client, Future

    from omtp_drake.scenario import Scenario

_log = logging.getLogger(__name__)

#: Seconds to connect to a scheduler and to wait for its first worker.
_CONNECT_TIMEOUT_S = 10.0
_WORKERS_TIMEOUT_S = 30.0
#: A local cluster's housekeeping, for a cluster of a few workers whose tasks are whole runs
#: (Dask's defaults suit a dashboard over many short tasks): no statistical profiler (it samples
#: every server's event loop every 10 ms, for the dashboard, which a local cluster here has
#: not), event-loop health checks every second instead of every 20 ms, system and memory
#: monitors every second or two instead of every 0.1-0.5 s. Idle, a cluster of two workers
#: burnt about 2.5 CPU s per 20 s with the defaults (profiler 0.5 of it) and 0.3 with these:
#: about 12 % of a core taken from the runs it serves. (distributed's own test clusters also turn
#: the profiler off and tick every 500 ms.)
_LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
    # A worker that died (a run killed it) is started again by its nanny; the cluster closes
    # that nanny, and the worker it is starting, when the new worker has not registered within
    # this time (Dask's 15 s). One core beside a busy loop, a restart took 25 s: the cluster
    # closed the new worker as it began the next task (a grade's next script then got
    # "worker died") and was left with no workers. 5 minutes: a restart on a slow machine.
    "distributed.deploy.lost-worker-timeout": "300s",
    # Worker processes forked from one server process that has imported distributed (started
    # with the first cluster of this process, kept for the next) instead of each a new
    # interpreter importing it again: two workers started in 3.1 CPU s instead of 5.0, a
    # second cluster of the same process in 0.5 instead of 3.5 (and 2 s of wall instead of
    # 12 at load 10), and a worker killed by a run comes back as fast. The server's
    # environment is its own first one: each cluster hands its workers this process's (the
    # Nanny's ``env``, see connect).
    "distributed.worker.multiprocessing-method": "forkserver",
}


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

    outcome = thread_sandbox().call(run_in_child, (job.spec, job.duration, job.run_fn), job.timeout)
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
    import dask
    from distributed import Client, LocalCluster

    free_meshcats_here()  # before the client's event loop thread runs Python
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
        dask.config.set(_LOCAL_CLUSTER_CONFIG),  # read as its servers start (its workers get a copy)
        LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            # Its HTTP server (health checks; no dashboard) on a free port: on Dask's 8787 each
            # cluster beside another on the machine warned "Port 8787 is already in use".
            scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
            silence_logs=logging.ERROR,
            # This process's environment now (a worker forked from the server has the server's).
            env=dict(os.environ),
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
    meta: dict[str, tuple[_Job, int, list[dict[str, Any]], int]] = {}

    def submit(job: _Job, attempt: int, failures: list[dict[str, Any]], avoid: str, lost: int = 0) -> None:
        workers = None
        if avoid:
            others = [w for w in client.has_what() if w != avoid]
            workers = others or None
        key = f"omtp-run-{job.spec.run_id}-{attempt}-{uuid.uuid4().hex[:8]}"
        # Only the other workers (a loose restriction would let an idle
        # worker steal the task back); any worker when there is no other.
        future = client.submit(_execute, job, key=key, pure=False, workers=workers)
        meta[future.key] = (job, attempt, failures, lost)
        pending.add(future)

    for job in jobs:
        submit(job, 1, [], "")
    for future in pending:
        job, attempt, failures, lost = meta.pop(future.key)
        record = _record_of(future, job)
        lost += _lost_workers(client, future.key)
        future.release()
        if record.status != FINISHED and attempt <= retries:
            _log.info("run %s: %s (%s); retrying", job.spec.run_id, record.status, record.message)
            failure = {"status": record.status, "message": record.message, "worker": record.worker}
            submit(job, attempt + 1, failures + [failure], record.worker, lost)
            continue
        record.attempts = attempt
        record.failed_attempts = failures
        record.lost_workers = lost
        if lost:
            _log.warning("run %s: its worker died %d time(s); Dask ran it again", job.spec.run_id, lost)
        on_record(record)


def _lost_workers(client: Client, key: str) -> int:
    """How many workers died while they held the task ``key`` (the scheduler's
    ``suspicious`` count: Dask runs such a task again on another worker, silently)."""

    def suspicious(dask_scheduler: Any) -> int:
        task = dask_scheduler.tasks.get(key)
        return int(task.suspicious) if task is not None else 0

    try:
        return int(client.run_on_scheduler(suspicious))
    except Exception as e:  # a scheduler that cannot answer: say so, count none
        _log.warning("cannot ask the scheduler about task %s (%s)", key, e)
        return 0


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
    store = ResultStore(Path(out), plan) if out is not None else None
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
    store: Optional[ResultStore],
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
