"""Screenshots of standalone Meshcat replays in headless chromium.

``screenshot(replay.html, out.png, time=2.0)`` opens a replay written by
``--record`` (see :func:`omtp_drake.viz.meshcat.save_recording`), waits until
every embedded Meshcat command has been applied, moves the recorded animation
to ``time`` (seconds of simulated time; default: its end), and saves what a
user would see in a 1280 x 800 browser window.

It drives Debian's ``chromium`` through the Chrome DevTools Protocol over a
pipe (``--remote-debugging-pipe``), so no Python package and no network port is
needed, and it waits on the page's own state rather than on a time budget:
``chromium --screenshot --virtual-time-budget`` hangs now and then on these
pages, which load their scene through ~200 ``fetch("data:...")`` calls.
"""

from __future__ import annotations

import base64
import fcntl
import json
import logging
import os
import queue
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time as _time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import BrowserError, ConfigError, UnknownNameError

_log = logging.getLogger(__name__)

#: Names under which Debian and other distributions install chromium.
BROWSER_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_browser() -> Optional[str]:
    """Path of the first chromium-like browser on PATH (``$OMTP_DRAKE_BROWSER`` first)."""
    names = [os.environ["OMTP_DRAKE_BROWSER"]] if os.environ.get("OMTP_DRAKE_BROWSER") else []
    for name in names + list(BROWSER_NAMES):
        path = shutil.which(name)
        if path:
            return path
    return None


# Runs in the page before its own scripts: remembers every fetch() and every
# Response.arrayBuffer() promise, so the page can tell when the replay's
# embedded commands (fetched from data: URLs, then decoded) have all arrived.
_TRACK_FETCHES = """
window.__omtpPending = [];
const omtpFetch = window.fetch.bind(window);
window.fetch = (...args) => { const p = omtpFetch(...args); window.__omtpPending.push(p); return p; };
const omtpArrayBuffer = Response.prototype.arrayBuffer;
Response.prototype.arrayBuffer = function () {
  const p = omtpArrayBuffer.call(this); window.__omtpPending.push(p); return p;
};
"""

# Resolves once no tracked promise is pending (the decode promises are created by
# the fetches' continuations, hence the loop), then one more task so that the
# last continuations (viewer.handle_command_bytearray) have run.
_SETTLE = """
(async () => {
  const tick = () => new Promise(resolve => setTimeout(resolve, 0));
  let seen = -1;
  while (seen !== window.__omtpPending.length) {
    seen = window.__omtpPending.length;
    await Promise.allSettled(window.__omtpPending.slice());
    await tick();
  }
  if (typeof viewer === "undefined") { return {ok: false, why: "no Meshcat viewer on the page"}; }
  return {ok: true, commands: seen, duration: viewer.animator.duration || 0};
})()
"""

# Unticks the visibility checkbox of each path in Meshcat's scene tree (what a
# user does in the controls); reports the paths that are not in the tree.
_HIDE = """
((paths) => {
  const missing = [];
  for (const path of paths) {
    let node = viewer.scene_tree;
    for (const name of path.split("/").filter(Boolean)) { node = node && node.children[name]; }
    if (node) { node.vis_controller.setValue(false); } else { missing.push(path); }
  }
  const top = Object.keys(viewer.scene_tree.children).map(name => "/" + name);
  return {missing: missing, valid: top};
})(%s)
"""

# Stops the replay's clock, puts every animation at TIME, and resolves after two
# rendered frames.
_SEEK = """
(async (time) => {
  const animator = viewer.animator;
  if (animator.playing) { animator.pause(); }
  animator.seek(time);
  animator.display_progress(time);
  viewer.set_dirty();
  const frame = () => new Promise(resolve => requestAnimationFrame(resolve));
  await frame(); await frame();
  return time;
})(%r)
"""


_TRAMPOLINE = (
    "import os, sys\n"
    "i, o = int(sys.argv[1]), int(sys.argv[2])\n"
    "os.dup2(i, 3); os.dup2(o, 4); os.close(i); os.close(o)\n"
    "os.execvp(sys.argv[3], sys.argv[3:])\n"
)


class _DevTools:
    """A minimal Chrome DevTools Protocol client over chromium's debugging pipe
    (requests on fd 3, replies and events on fd 4, NUL-separated JSON)."""

    def __init__(self, command: list[str]):
        self._browser = command[0]
        to_browser_r, to_browser_w = os.pipe()
        from_browser_r, from_browser_w = os.pipe()
        # The child's ends go to fds >= 10 so that a trampoline (a fresh Python,
        # safe where a preexec_fn is not: the caller may run threads, e.g.
        # Meshcat's server) can move them to 3 and 4 without clobbering one
        # another, then exec the browser.
        child_in = fcntl.fcntl(to_browser_r, fcntl.F_DUPFD_CLOEXEC, 10)
        child_out = fcntl.fcntl(from_browser_w, fcntl.F_DUPFD_CLOEXEC, 10)
        os.close(to_browser_r)
        os.close(from_browser_w)
        try:
            self.process = subprocess.Popen(
                [sys.executable, "-c", _TRAMPOLINE, str(child_in), str(child_out), *command],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                pass_fds=(child_in, child_out),
                start_new_session=True,
            )
        finally:
            os.close(child_in)
            os.close(child_out)
        self._out = os.fdopen(to_browser_w, "wb", buffering=0)
        self._in = os.fdopen(from_browser_r, "rb", buffering=0)
        self._next_id = 0
        self._replies: dict[int, queue.Queue[dict]] = {}
        self._events: queue.Queue[dict] = queue.Queue()
        self._lock = threading.Lock()
        self._closed = False
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        buffer = b""
        while True:
            chunk = self._in.read(1 << 16)
            if not chunk:  # the browser exited (or never started): wake every waiter
                with self._lock:
                    self._closed = True
                    for box in self._replies.values():
                        box.put({"closed": True})
                self._events.put({"method": "__closed__"})
                return
            buffer += chunk
            while b"\0" in buffer:
                raw, buffer = buffer.split(b"\0", 1)
                message = json.loads(raw)
                if "id" in message:
                    with self._lock:
                        reply_box = self._replies.get(message["id"])
                    if reply_box is not None:
                        reply_box.put(message)
                else:
                    self._events.put(message)

    def call(
        self, method: str, params: Optional[dict] = None, *, session: Optional[str] = None, deadline: float
    ) -> dict:
        with self._lock:
            if self._closed:
                raise BrowserError(self._exited(method))
            self._next_id += 1
            ident = self._next_id
            box: queue.Queue[dict] = queue.Queue()
            self._replies[ident] = box
        message: dict[str, Any] = {"id": ident, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        try:
            self._out.write(json.dumps(message).encode() + b"\0")
            reply = box.get(timeout=max(0.0, deadline - _time.monotonic()))
        except BrokenPipeError:
            raise BrowserError(self._exited(method)) from None
        except queue.Empty:
            raise BrowserError(f"chromium did not answer {method} in time") from None
        finally:
            with self._lock:
                self._replies.pop(ident, None)
        if reply.get("closed"):
            raise BrowserError(self._exited(method))
        if "error" in reply:
            raise BrowserError(f"chromium refused {method}: {reply['error'].get('message')}")
        return reply.get("result", {})

    def _exited(self, method: str) -> str:
        try:
            code = self.process.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            code = None
        return f"the browser exited (code {code}) before answering {method}; is {self._browser!r} a chromium?"

    def wait_event(self, method: str, *, deadline: float) -> dict:
        while True:
            try:
                event = self._events.get(timeout=max(0.0, deadline - _time.monotonic()))
            except queue.Empty:
                raise BrowserError(f"timed out waiting for chromium's {method}") from None
            if event.get("method") == "__closed__":
                raise BrowserError(f"chromium exited while waiting for {method}")
            if event.get("method") == method:
                return event

    def close(self) -> None:
        try:
            self._out.close()
        except OSError:
            pass
        try:  # chromium's helper processes too, or they keep the CPU busy
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait()
        self._in.close()


def screenshot(
    html: str | Path,
    png: str | Path,
    *,
    time: Optional[float] = None,
    size: tuple[int, int] = (1280, 800),
    hide: Sequence[str] = (),
    timeout_s: float = 120.0,
    browser: Optional[str] = None,
) -> Path:
    """Renders the standalone replay ``html`` and writes a PNG of it to ``png``.

    ``time`` is the replay time (s) to show; ``None`` shows the end of the
    recording (a file without an animation is shown as it is). ``hide`` lists
    Meshcat paths to switch off first, as with the visibility checkboxes in
    Meshcat's controls (e.g. ``/frusta``, ``/detections``,
    ``/frusta/logical_camera_1``); a path that is not in the scene raises
    :class:`UnknownNameError` listing the top-level paths. Raises
    :class:`BrowserError` if no browser is found or it does not finish within
    ``timeout_s``, and :class:`ConfigError` for a missing file or a bad size or
    time. Software rendering (SwiftShader) takes 3-15 s on 2 cores.
    """
    html = Path(html).resolve()
    png = Path(png)
    if not html.is_file():
        raise ConfigError(f"replay {str(html)!r} does not exist (write one with --record)")
    width, height = size
    if not (64 <= width <= 8192 and 64 <= height <= 8192):
        raise ConfigError(f"screenshot size {size!r} is outside 64..8192 pixels per side")
    if time is not None and not time >= 0.0:
        raise ConfigError(f"replay time {time!r} must be >= 0 s")
    browser = browser or find_browser()
    if browser is None:
        raise BrowserError(
            f"no headless browser found on PATH (looked for: "
            f"{', '.join(BROWSER_NAMES)}); on Debian: apt-get install chromium"
        )
    deadline = _time.monotonic() + timeout_s
    with tempfile.TemporaryDirectory(prefix="omtp_chromium_") as profile:
        command = [
            browser,
            "--headless=new",
            "--remote-debugging-pipe",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--no-default-browser-check",
            "--mute-audio",
            f"--user-data-dir={profile}",
            f"--window-size={width},{height}",
            "about:blank",
        ]
        tools = _DevTools(command)
        try:
            image, shown = _render(tools, html, time, width, height, list(hide), deadline)
        finally:
            tools.close()
    png.parent.mkdir(parents=True, exist_ok=True)
    png.write_bytes(image)
    _log.info("screenshot of %s at t = %.2f s written to %s", html.name, shown, png)
    return png


def _render(
    tools: _DevTools,
    html: Path,
    time: Optional[float],
    width: int,
    height: int,
    hide: list[str],
    deadline: float,
) -> tuple[bytes, float]:
    target = tools.call("Target.createTarget", {"url": "about:blank"}, deadline=deadline)
    session = tools.call(
        "Target.attachToTarget", {"targetId": target["targetId"], "flatten": True}, deadline=deadline
    )["sessionId"]

    def call(method: str, params: Optional[dict] = None) -> dict:
        return tools.call(method, params, session=session, deadline=deadline)

    def evaluate(expression: str) -> Any:
        result = call(
            "Runtime.evaluate", {"expression": expression, "awaitPromise": True, "returnByValue": True}
        )
        if "exceptionDetails" in result:
            detail = result["exceptionDetails"]
            text = detail.get("exception", {}).get("description") or detail.get("text")
            raise BrowserError(f"the replay page failed: {text}")
        return result["result"].get("value")

    call("Page.enable")
    call("Runtime.enable")
    call(
        "Emulation.setDeviceMetricsOverride",
        {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
    )
    call("Page.addScriptToEvaluateOnNewDocument", {"source": _TRACK_FETCHES})
    call("Page.navigate", {"url": html.as_uri()})
    tools.wait_event("Page.loadEventFired", deadline=deadline)
    state = evaluate(_SETTLE)
    if not state or not state.get("ok"):
        raise BrowserError(
            f"{html.name} is not a Meshcat replay: {(state or {}).get('why', 'the page did not load')}"
        )
    duration = float(state["duration"])
    if time is not None and duration > 0.0 and time > duration:
        raise ConfigError(f"replay time {time} s is past the end of {html.name} (0..{duration:.2f} s)")
    if hide:
        hidden = evaluate(_HIDE % json.dumps(hide))
        if hidden["missing"]:
            raise UnknownNameError(
                "Meshcat path",
                hidden["missing"][0],
                hidden["valid"] + ["/frusta/<camera>", "/detections/<camera>"],
            )
    shown = duration if time is None else float(time)
    if duration > 0.0:
        evaluate(_SEEK % shown)
    else:
        evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    data = call("Page.captureScreenshot", {"format": "png"})["data"]
    return base64.b64decode(data), shown
