"""The notebooks in notebooks/: each runs top to bottom (fast mode), and is committed without outputs."""

import asyncio
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


def _execute(path: Path, workdir: Path) -> nbformat.NotebookNode:
    book = nbformat.read(path, as_version=4)
    # Kernel "python3" is ipykernel's native kernel: it runs with this interpreter
    # (sys.executable), so a fresh `pip install -e ".[test]"` venv is all it needs. Once the
    # last cell has run, the kernel is stopped at once (its graceful shutdown cost 0.2-0.4 s
    # a notebook): a notebook closes what it opened in its cells (05's Dask cluster).
    client = NotebookClient(book, timeout=300, kernel_name="python3", shutdown_kernel="immediate",
                            resources={"metadata": {"path": str(workdir)}})
    asyncio.run(client.async_execute())
    return book


#: The longest first (05: a recorded run and a Dask batch; the others 5-8 CPU s): with
#: `--dist worksteal` a long test started last runs alone at the end of the suite.
_ORDER = sorted(NOTEBOOKS, key=lambda p: p.name != LONGEST)


@pytest.mark.parametrize("path", _ORDER, ids=lambda p: p.stem)
def test_notebook_runs(path, tmp_path, monkeypatch):
    """Executes the notebook (OMTP_NOTEBOOK_FAST=1) in a kernel of its own, a test each (one
    test of all six took 50 CPU s, the suite's longest); any cell error fails the test. It
    shows at least one figure and records a Meshcat replay."""
    monkeypatch.setenv("OMTP_NOTEBOOK_FAST", "1")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    workdir = tmp_path / path.stem
    workdir.mkdir()
    monkeypatch.setenv("TMPDIR", str(tmp_path))  # the notebook's replay goes there
    try:
        book = _execute(path, workdir)
    except CellExecutionError as e:
        pytest.fail(str(e)[-2000:])
    outputs = [o for c in book.cells if c.cell_type == "code" for o in c.outputs]
    assert not any(o.output_type == "error" for o in outputs), "error output"
    assert any("image/png" in o.get("data", {}) for o in outputs), "no figure shown"
    replays = sorted(p.name for p in tmp_path.rglob("*.html"))
    assert len(replays) == 1, replays
