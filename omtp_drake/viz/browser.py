"""Screenshots of standalone Meshcat replays in headless chromium.

``screenshot(replay.html, out.png, time=2.0)`` opens a replay written by
``--record`` (see :func:`omtp_drake.viz.meshcat.save_recording`), waits until
every embedded Meshcat command has been applied, moves the recorded animation
to ``time`` (seconds of simulated time; default: its end), and saves what a
user would see in a 1280 x 800 browser window. ``screenshots(replay.html, [Shot(...), ...])``
takes several pictures of one replay (other times, sizes, hidden paths) in one page load: the
browser's start and the replay's ~200 decoded commands are paid once, not once a picture.
The browser itself is started once a process and kept (:mod:`omtp_drake.viz.browser_host`),
and so is the page of the last replay shown: another call for the same file, unchanged, takes
its pictures without loading it again (Meshcat's page, its WebGL context and shaders cost
chromium 3-4 CPU s a load, even for a replay of three shapes); a kept page draws nothing
meanwhile.

It drives the system's chromium (``find_browser``) through Playwright, which
downloads nothing when given the browser's path, and it waits on the page's
own state rather than on a time budget: ``chromium --screenshot
--virtual-time-budget`` hangs now and then on these pages, which load their
scene through ~200 ``fetch("data:...")`` calls.
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import time as _time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.errors import BrowserError, ConfigError, UnknownNameError
from omtp_drake.viz.browser_host import BrowserThread, on_browser_thread

if TYPE_CHECKING:
    from playwright.sync_api import Page

_log = logging.getLogger(__name__)

#: Names under which Debian and other distributions install chromium.
BROWSER_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

#: Switches added to Playwright's own: software WebGL (SwiftShader), as on a machine without a GPU;
#: the page's layers composited in software rather than through SwiftShader too (about 11 % less CPU).
_CHROMIUM_ARGS = (
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-gpu-compositing",
    "--mute-audio",
)


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
# embedded commands (fetched from data: URLs, then decoded) have all arrived; and
# gates requestAnimationFrame, so that a kept page can be held (see _HOLD_FRAMES).
_TRACK_FETCHES = """
window.__omtpPending = [];
const omtpFetch = window.fetch.bind(window);
window.fetch = (...args) => { const p = omtpFetch(...args); window.__omtpPending.push(p); return p; };
const omtpArrayBuffer = Response.prototype.arrayBuffer;
Response.prototype.arrayBuffer = function () {
  const p = omtpArrayBuffer.call(this); window.__omtpPending.push(p); return p;
};
window.__omtpHeld = null;
const omtpFrame = window.requestAnimationFrame.bind(window);
window.requestAnimationFrame = (callback) => {
  if (window.__omtpHeld !== null) { window.__omtpHeld.push(callback); return 0; }
  return omtpFrame(callback);
};
window.__omtpRelease = () => {
  const held = window.__omtpHeld || [];
  window.__omtpHeld = null;
  for (const callback of held) { omtpFrame(callback); }
};
"""

# Holds the page's animation frames while it is kept between calls (a Meshcat page left open
# redraws its stats panel every frame: 0.16 CPU s a second); __omtpRelease() lets them go.
_HOLD_FRAMES = "window.__omtpHeld = window.__omtpHeld || []"

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

# Sets the visibility checkbox of each path in Meshcat's scene tree (what a user
# does in the controls) to VISIBLE (null: none, a check); reports the paths that are not in the
# tree (and then sets none).
_SET_VISIBLE = """
((paths, visible) => {
  const missing = [], found = [];
  for (const path of paths) {
    let node = viewer.scene_tree;
    for (const name of path.split("/").filter(Boolean)) { node = node && node.children[name]; }
    if (node) { found.push(node); } else { missing.push(path); }
  }
  if (missing.length === 0 && visible !== null) {
    for (const node of found) { node.vis_controller.setValue(visible); }
  }
  const top = Object.keys(viewer.scene_tree.children).map(name => "/" + name);
  return {missing: missing, valid: top};
})(%s, %s)
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


#: Side (pixels) of the window the replay loads in, before the shots' own sizes.
_LOAD_SIZE = 64


@dataclass(frozen=True)
class Shot:
    """One picture of a replay: written to ``png``, the replay at ``time`` (s; ``None``: its
    end), in a ``size`` (width, height) window, with the Meshcat paths of ``hide`` switched off."""

    png: str | Path
    time: Optional[float] = None
    size: tuple[int, int] = (1280, 800)
    hide: Sequence[str] = ()


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
    (written,) = screenshots(html, [Shot(png, time, size, tuple(hide))], timeout_s=timeout_s, browser=browser)
    return written


def screenshots(
    html: str | Path, shots: Sequence[Shot], *, timeout_s: float = 120.0, browser: Optional[str] = None
) -> list[Path]:
    """Renders the standalone replay ``html`` once and writes each of ``shots`` (see
    :class:`Shot`; the rules of :func:`screenshot`), in their order; returns their paths.
    Every shot is checked before the browser starts, and against the replay before the first
    is drawn: a shot the replay refuses (a time past its end, a path not in its scene) stops
    the run, and no PNG is written.
    ``timeout_s`` bounds the whole run."""
    html = Path(html).resolve()
    if not shots:
        raise ConfigError("screenshots needs at least one Shot")
    for shot in shots:
        _check_request(html, shot.size, shot.time)
    browser = browser or find_browser()
    if browser is None:
        raise BrowserError(
            f"no headless browser found on PATH (looked for: "
            f"{', '.join(BROWSER_NAMES)}); on Debian: apt-get install chromium"
        )
    images = on_browser_thread(_capture, browser, html, list(shots), timeout_s, timeout_s=timeout_s + 30.0)
    written = []
    for shot, (image, shown) in zip(shots, images):
        png = Path(shot.png)
        png.parent.mkdir(parents=True, exist_ok=True)
        png.write_bytes(image)
        _log.info("screenshot of %s at t = %.2f s written to %s", html.name, shown, png)
        written.append(png)
    return written


@dataclass
class _Kept:
    """A loaded replay page, kept on the browser's thread for the next call on the same file."""

    key: tuple[str, int, int]  # the replay's path, mtime (ns) and size when it was loaded
    browser: Any
    context: Any
    page: Any
    duration: float

    def close(self) -> None:
        from playwright.sync_api import Error as PlaywrightError

        try:
            self.context.close()
        except PlaywrightError:  # its browser has gone: nothing left to close
            pass


def _capture(
    thread: BrowserThread, browser: str, html: Path, shots: list[Shot], timeout_s: float
) -> list[tuple[bytes, float]]:
    """On the browser's ``thread``: the loaded page of ``html`` (kept from the last call if
    that was of this file unchanged, else loaded now in a fresh page of the running ``browser``,
    launched if need be); returns each shot's (PNG bytes, replay time shown). The page is kept
    after the shots, or after a shot refused before it changed the page; else closed."""
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    deadline = _time.monotonic() + timeout_s
    try:
        chromium = thread.browser(browser, _CHROMIUM_ARGS, _ms_left(deadline))
    except PlaywrightError as e:
        first = str(e).splitlines()[0]
        raise BrowserError(
            f"the browser exited before starting ({first}); is {browser!r} a chromium?"
        ) from None
    kept = None
    try:
        kept = _page_of(thread, chromium, html, deadline)
        for shot in shots:
            _check_time(html, kept.duration, shot.time)
        _set_visible(kept.page, [path for shot in shots for path in shot.hide], None, deadline)  # a check
        images = [_render(kept.page, html, kept.duration, shot, deadline) for shot in shots]
        thread.kept["replay"], kept = _held(kept), None
        return images
    except (ConfigError, UnknownNameError):
        thread.kept["replay"], kept = _held(kept), None  # refused before changing the page
        raise
    except PlaywrightTimeout:
        raise BrowserError(f"chromium did not finish {html.name} within {timeout_s} s") from None
    except PlaywrightError as e:
        raise BrowserError(f"chromium failed on {html.name}: {str(e).splitlines()[0]}") from None
    finally:
        if kept is not None:
            kept.close()


def _page_of(thread: BrowserThread, chromium: Any, html: Path, deadline: float) -> _Kept:
    """The kept page of ``html`` if it is of this file as it is now, in this browser (its
    frames let go); else the kept page (or a new one) that has loaded ``html`` now: a page
    that opens another file keeps its renderer process (a new page's costs chromium ~1 CPU s)."""
    from playwright.sync_api import Error as PlaywrightError

    stat = html.stat()
    key = (str(html), stat.st_mtime_ns, stat.st_size)
    kept: Optional[_Kept] = thread.kept.pop("replay", None)
    if kept is not None:
        try:
            if kept.browser is chromium and not kept.page.is_closed():
                if kept.key == key:
                    kept.page.evaluate("window.__omtpRelease()")
                    return kept
                return _reload(kept, key, html, deadline)
        except PlaywrightError:  # the page has crashed: load the replay in a new one
            pass
        kept.close()
    # The page loads in a small window: the replay plays its animation as it loads, each frame
    # drawn in software (SwiftShader); each shot sets its own size before it is drawn.
    try:
        context = chromium.new_context(
            viewport={"width": _LOAD_SIZE, "height": _LOAD_SIZE}, device_scale_factor=1
        )
    except PlaywrightError as e:
        raise BrowserError(f"chromium failed to open a page: {str(e).splitlines()[0]}") from None
    fresh = _Kept(key, chromium, context, None, 0.0)
    try:
        fresh.page = context.new_page()
        fresh.page.add_init_script(_TRACK_FETCHES)
        return _reload(fresh, key, html, deadline)
    except BaseException:
        fresh.close()
        raise


def _reload(kept: _Kept, key: tuple[str, int, int], html: Path, deadline: float) -> _Kept:
    """``kept``'s page with ``html`` loaded in it (in the small window); closed if it fails."""
    try:
        kept.key, kept.duration = key, 0.0
        kept.page.set_viewport_size({"width": _LOAD_SIZE, "height": _LOAD_SIZE})
        kept.duration = _load(kept.page, html, deadline)
    except BaseException:
        kept.close()
        raise
    return kept


def _held(kept: Optional[_Kept]) -> Optional[_Kept]:
    """``kept`` with its page's frames held (it draws nothing until the next call); None
    (and the page closed) if the page does not answer."""
    from playwright.sync_api import Error as PlaywrightError

    if kept is not None:
        try:
            kept.page.evaluate(_HOLD_FRAMES)
        except PlaywrightError:
            kept.close()
            return None
    return kept


def _check_request(html: Path, size: tuple[int, int], time: Optional[float]) -> None:
    """Raises :class:`ConfigError` for a missing replay, a size out of range or a negative time."""
    if not html.is_file():
        raise ConfigError(f"replay {str(html)!r} does not exist (write one with --record)")
    width, height = size
    if not (64 <= width <= 8192 and 64 <= height <= 8192):
        raise ConfigError(f"screenshot size {size!r} is outside 64..8192 pixels per side")
    if time is not None and not time >= 0.0:
        raise ConfigError(f"replay time {time!r} must be >= 0 s")


def _ms_left(deadline: float) -> float:
    """Milliseconds until ``deadline`` (Playwright's unit), at least 1."""
    return max(1.0, (deadline - _time.monotonic()) * 1000.0)


def _evaluate(page: Page, expression: str, deadline: float) -> Any:
    """Awaits the page's ``expression`` and returns its value; the page's clock bounds the wait."""
    from playwright.sync_api import Error as PlaywrightError

    ms = round(_ms_left(deadline))
    timeout = f"new Promise((_, no) => setTimeout(() => no(new Error('timed out after {ms} ms')), {ms}))"
    try:
        return page.evaluate(f"Promise.race([{expression}, {timeout}])")
    except PlaywrightError as e:
        raise BrowserError(f"the replay page failed: {str(e).splitlines()[0]}") from None


def _load(page: Page, html: Path, deadline: float) -> float:
    """Opens ``html`` (in ``page``, whose init script is _TRACK_FETCHES) and waits until its
    replay's commands are applied; returns its duration (s)."""
    page.goto(html.as_uri(), wait_until="load", timeout=_ms_left(deadline))
    state = _evaluate(page, _SETTLE, deadline)
    if not state or not state.get("ok"):
        raise BrowserError(
            f"{html.name} is not a Meshcat replay: {(state or {}).get('why', 'the page did not load')}"
        )
    return float(state["duration"])


def _check_time(html: Path, duration: float, time: Optional[float]) -> None:
    """Raises :class:`ConfigError` for a time past the end of the replay's animation."""
    if time is not None and duration > 0.0 and time > duration:
        raise ConfigError(f"replay time {time} s is past the end of {html.name} (0..{duration:.2f} s)")


def _set_visible(page: Page, paths: Sequence[str], visible: Optional[bool], deadline: float) -> None:
    """Ticks (``visible``) or unticks the paths' checkboxes (None: neither); a path not in the
    scene raises, and then none is changed."""
    if not paths:
        return
    result = _evaluate(page, _SET_VISIBLE % (json.dumps(list(paths)), json.dumps(visible)), deadline)
    if result["missing"]:
        valid = result["valid"] + ["/frusta/<camera>", "/detections/<camera>"]
        raise UnknownNameError("Meshcat path", result["missing"][0], valid)


def _render(page: Page, html: Path, duration: float, shot: Shot, deadline: float) -> tuple[bytes, float]:
    """One shot of the loaded replay; what it hid is shown again afterwards (the next shot's
    scene is the replay's own)."""
    width, height = shot.size
    page.set_viewport_size({"width": width, "height": height})
    _set_visible(page, shot.hide, False, deadline)
    shown = duration if shot.time is None else float(shot.time)
    if duration > 0.0:
        _evaluate(page, _SEEK % shown, deadline)
    else:
        _evaluate(page, "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", deadline)
    image = page.screenshot(type="png", timeout=_ms_left(deadline))
    _set_visible(page, shot.hide, True, deadline)
    return image, shown
