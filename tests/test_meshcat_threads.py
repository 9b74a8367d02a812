"""Drake's Meshcat must be destroyed on the thread that made it, or the process aborts
(``IsThread(main_thread_id_)`` in meshcat.cc). A dropped cell that held one is freed by
Python's cycle collector on whichever thread triggers it: before the library starts a
thread of Python code (a Dask client's loop here), it frees that garbage on its own thread.
Seen before the fix: a batch after a test that had dropped a Meshcat cell killed its xdist
worker with "Fatal Python error: Aborted" while garbage-collecting in Dask's thread."""

import subprocess
import sys

SCRIPT = """
import gc, threading
from pydrake.geometry import Meshcat
from omtp_drake.batch.cluster import connect

class Cell:  # a cell dropped in a reference cycle, as a notebook's cells often are
    pass

cell = Cell()
cell.meshcat, cell.me = Meshcat(), cell
del cell
# The main thread's own collector runs when allocations reach its thresholds: an old cycle may
# wait long for it. Off here, so that only an explicit collection frees the cycle.
gc.disable()
with connect(workers=1):
    collector = threading.Thread(target=gc.collect)  # what any thread's allocation may trigger
    collector.start()
    collector.join()
print("alive")
"""


def test_a_dropped_meshcat_cell_does_not_abort_the_process_when_a_batch_thread_collects():
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "alive" in done.stdout, done.stderr[-2000:]


#: A screenshot (from a script, or from a running asyncio loop as in a Jupyter kernel's cell)
#: runs Playwright on the process's browser thread; whatever that thread's allocations collect
#: is stood in for here by the job itself collecting.
SCREENSHOT_SCRIPT = """
import asyncio, gc
from pydrake.geometry import Meshcat
from omtp_drake.viz import browser_host

class Cell:
    pass

cell = Cell()
cell.meshcat, cell.me = Meshcat(), cell
del cell
gc.disable()

async def notebook_cell():
    return browser_host.on_browser_thread(lambda thread: gc.collect(), timeout_s=60)

asyncio.run(notebook_cell())
print("alive")
"""


def test_a_dropped_meshcat_cell_does_not_abort_a_screenshot_taken_from_a_notebook():
    """Seen as 'Fatal Python error: Aborted' while Playwright's thread imported its modules,
    in test_replay_render's pictures after the recorded run was dropped."""
    done = subprocess.run(
        [sys.executable, "-c", SCREENSHOT_SCRIPT], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0 and "alive" in done.stdout, done.stderr[-2000:]
