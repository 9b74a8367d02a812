"""One headless chromium per process, kept for all of the process's screenshots.

Starting Playwright's driver and chromium costs 1-3 s of a screenshot (more on a busy
machine); a user who takes several pictures (a notebook, a script, the tests) pays it once.
Playwright's sync API belongs to the thread that started it and refuses a thread that runs
an asyncio loop (a Jupyter kernel's), so the browser lives on a thread of its own, which
runs each screenshot's work in turn (:func:`on_browser_thread`). A browser that has gone
away (crashed, killed) is launched again at the next screenshot; the process closes it at
exit (:func:`close_browsers`).

That thread runs Python code: garbage freed there may hold a Drake Meshcat, which must die
on the thread that made it (see :func:`omtp_drake.viz.meshcat.free_meshcats_here`), so the
caller's garbage is freed on the caller's thread before each job.
"""

from __future__ import annotations

import atexit
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from queue import SimpleQueue
from typing import Any, Optional, TypeVar

from omtp_drake.errors import BrowserError

T = TypeVar("T")


class BrowserThread:
    """The thread that owns Playwright and the browsers it launched (one per executable)."""

    def __init__(self) -> None:
        self._jobs: SimpleQueue[Optional[Callable[[], None]]] = SimpleQueue()
        self._playwright: Any = None
        self._browsers: dict[str, Any] = {}
        #: What jobs keep between calls, by name (a loaded page); only touched on this thread.
        self.kept: dict[str, Any] = {}
        self._thread = threading.Thread(target=self._serve, name="omtp-drake-browser", daemon=True)
        self._thread.start()

    def call(self, function: Callable[..., T], *args: Any, timeout_s: Optional[float] = None) -> T:
        """``function(self, *args)`` on this thread; its result, or what it raised."""
        future: Future[T] = Future()

        def job() -> None:
            try:
                future.set_result(function(self, *args))
            except BaseException as e:  # handed to the caller, as Future does
                future.set_exception(e)

        self._jobs.put(job)
        return future.result(timeout=timeout_s)

    def browser(self, executable: str, args: Sequence[str], timeout_ms: float) -> Any:
        """The running chromium ``executable`` (launched now if it is not running). Only on
        this thread (inside :meth:`call`)."""
        running = self._browsers.get(executable)
        if running is not None and running.is_connected():
            return running
        if self._playwright is None:
            from playwright.sync_api import sync_playwright

            self._playwright = sync_playwright().start()
        launched = self._playwright.chromium.launch(
            executable_path=executable, args=list(args), timeout=timeout_ms
        )
        self._browsers[executable] = launched
        return launched

    def stop(self, timeout_s: float) -> None:
        """Closes the browsers and Playwright, then ends the thread (waits ``timeout_s`` at most)."""
        self._jobs.put(None)
        self._thread.join(timeout_s)

    def _serve(self) -> None:
        while (job := self._jobs.get()) is not None:
            job()
        for launched in self._browsers.values():
            try:
                launched.close()
            except Exception:  # already gone: nothing to close
                pass
        if self._playwright is not None:
            self._playwright.stop()


_lock = threading.Lock()
_host: list[BrowserThread] = []  # the process's browser thread, once a screenshot started it


def on_browser_thread(function: Callable[..., T], *args: Any, timeout_s: float) -> T:
    """``function(thread, *args)`` on the process's browser thread (started now if need be),
    where ``thread.browser(...)`` gives the running chromium. A job that has not ended
    ``timeout_s`` after it started (a wedged browser; its own waits end sooner) raises
    :class:`BrowserError`, and the next screenshot starts a fresh thread."""
    from omtp_drake.viz.meshcat import free_meshcats_here

    with _lock:
        if not _host:
            _host.append(BrowserThread())
            atexit.register(close_browsers)
        host = _host[0]
    free_meshcats_here()  # before the browser's thread runs Python (a dropped cell's Meshcat)
    try:
        return host.call(function, *args, timeout_s=timeout_s)
    except FutureTimeout:
        with _lock:
            if _host and _host[0] is host:
                _host.clear()
        raise BrowserError(f"the browser did not answer within {timeout_s:.0f} s") from None


def close_browsers(timeout_s: float = 10.0) -> None:
    """Closes the process's browser (a later screenshot starts another); at exit too."""
    with _lock:
        hosts = list(_host)
        _host.clear()
    for host in hosts:
        host.stop(timeout_s)
