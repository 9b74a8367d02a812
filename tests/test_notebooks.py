"""The notebooks in notebooks/: each runs top to bottom (fast mode), and is committed without outputs."""

import asyncio
from concurrent.futures import ThreadPoolExecutor
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
    # (sys.executable), so a fresh `pip install -e ".[test]"` venv is all it needs.
    client = NotebookClient(book, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(workdir)}})
    asyncio.run(client.async_execute())  # one event loop per thread
    return book


def test_notebooks_run(tmp_path, monkeypatch):
    """Executes every notebook (OMTP_NOTEBOOK_FAST=1), two at a time (the kernels
    wait on I/O a good part of the time); any cell error fails the test. Each
    shows at least one figure and records a Meshcat replay."""
    monkeypatch.setenv("OMTP_NOTEBOOK_FAST", "1")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    workdirs = {p: tmp_path / p.stem for p in NOTEBOOKS}
    for d in workdirs.values():
        d.mkdir()
    monkeypatch.setenv("TMPDIR", str(tmp_path))  # the notebooks' replays go there
    # The longest first (05: a recorded run and a Dask batch, ~24 s alone; the others 5-8 s):
    # started last, it would run alone after the others.
    order = sorted(NOTEBOOKS, key=lambda p: p.name != LONGEST)
    with ThreadPoolExecutor(max_workers=3) as pool:
        futures = {p: pool.submit(_execute, p, workdirs[p]) for p in order}
    failures = {}
    for path, future in futures.items():
        try:
            book = future.result()
        except CellExecutionError as e:
            failures[path.name] = str(e)[-2000:]
            continue
        outputs = [o for c in book.cells if c.cell_type == "code" for o in c.outputs]
        if any(o.output_type == "error" for o in outputs):
            failures[path.name] = "error output"
        elif not any("image/png" in o.get("data", {}) for o in outputs):
            failures[path.name] = "no figure shown"
    assert not failures, failures
    replays = sorted(p.name for p in tmp_path.rglob("*.html"))
    assert len(replays) == len(NOTEBOOKS), replays
