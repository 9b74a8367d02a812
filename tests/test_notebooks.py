"""The notebooks in notebooks/: each runs top to bottom (fast mode), and is committed without outputs."""

import asyncio
import os
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))
#: The notebook that takes the longest in fast mode.
LONGEST = "05_fill_a_bin.ipynb"


def test_there_are_notebooks():
    assert [p.name[:3] for p in NOTEBOOKS] == ["01_", "02_", "03_", "04_", "05_", "06_"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_is_committed_without_outputs(path):
    book = nbformat.read(path, as_version=4)
    nbformat.validate(book)
    for cell in book.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]


class SharedKernel:
    """One IPython kernel for the notebooks a test process runs, one after the other: its
    start and the imports of drake, omtp_drake, matplotlib and Dask (4-5 CPU s of each
    notebook's 6-12) are paid once. Before each notebook, the names the last one left in the
    user namespace are deleted (``%reset -f`` would delete ``__spec__`` too, which Dask's
    spawned workers read from ``__main__``; a notebook that uses a name it does not define or
    import itself fails, as in a fresh kernel), and the notebook's folder and temporary
    folder are set; only imported modules carry over. Kernel "python3" is ipykernel's native
    kernel: it runs with this interpreter (sys.executable), so a fresh `pip install -e
    ".[test]"` venv is all it needs."""

    def __init__(self, cwd: Path) -> None:
        self.loop = asyncio.new_event_loop()
        env = {**os.environ, "OMTP_NOTEBOOK_FAST": "1", "MPLBACKEND": "module://matplotlib_inline.backend_inline"}
        # Stopped at once when done (a graceful shutdown cost 0.2-0.4 s): a notebook closes
        # what it opened in its cells (05's Dask cluster).
        self.client = NotebookClient(nbformat.v4.new_notebook(), timeout=300, kernel_name="python3",
                                     shutdown_kernel="immediate")
        self.client.km = self.client.create_kernel_manager()
        self.loop.run_until_complete(self.client.async_start_new_kernel(cwd=str(cwd), env=env))
        self.loop.run_until_complete(self.client.async_start_new_kernel_client())
        self._run_alone("_FRESH = set(globals()) | {'_FRESH'}")

    def _run_alone(self, source: str) -> None:
        """Runs ``source`` in the kernel as a notebook of one cell, outside the history."""
        cell = nbformat.v4.new_code_cell(source)
        self.client.nb = nbformat.v4.new_notebook(cells=[cell])
        self.loop.run_until_complete(self.client.async_execute_cell(cell, 0, store_history=False))

    def run(self, path: Path, workdir: Path, tmp: Path) -> nbformat.NotebookNode:
        """Runs the notebook at ``path`` top to bottom in ``workdir`` (its temporary files in
        ``tmp``); a cell's error raises CellExecutionError."""
        book = nbformat.read(path, as_version=4)
        self._run_alone(
            "[globals().pop(name) for name in set(globals()) - _FRESH]\n"
            f"__import__('os').chdir({str(workdir)!r})\n"
            f"__import__('os').environ['TMPDIR'] = __import__('tempfile').tempdir = {str(tmp)!r}")
        client = self.client
        client.nb = book
        client.reset_execution_trackers()
        for index, cell in enumerate(book.cells):
            self.loop.run_until_complete(client.async_execute_cell(cell, index, execution_count=index + 1))
        return book

    def close(self) -> None:
        self.loop.run_until_complete(self.client._async_cleanup_kernel())
        self.loop.close()


@pytest.fixture(scope="module")
def kernel(tmp_path_factory):
    shared = SharedKernel(tmp_path_factory.mktemp("kernel"))
    yield shared
    shared.close()


#: The longest first (05: a recorded run and a Dask batch; the others 5-8 CPU s): with
#: `--dist worksteal` a long test started last runs alone at the end of the suite.
_ORDER = sorted(NOTEBOOKS, key=lambda p: p.name != LONGEST)


@pytest.mark.parametrize("path", _ORDER, ids=lambda p: p.stem)
def test_notebook_runs(path, kernel, tmp_path):
    """Executes the notebook (OMTP_NOTEBOOK_FAST=1) top to bottom in the process's shared
    kernel, a test each (one test of all six was the suite's longest); any cell error fails
    the test. It shows at least one figure and records a Meshcat replay."""
    workdir = tmp_path / path.stem
    workdir.mkdir()
    try:
        book = kernel.run(path, workdir, tmp_path)  # the notebook's replay goes to tmp_path
    except CellExecutionError as e:
        pytest.fail(str(e)[-2000:])
    outputs = [o for c in book.cells if c.cell_type == "code" for o in c.outputs]
    assert not any(o.output_type == "error" for o in outputs), "error output"
    assert any("image/png" in o.get("data", {}) for o in outputs), "no figure shown"
    replays = sorted(p.name for p in tmp_path.rglob("*.html"))
    assert len(replays) == 1, replays
