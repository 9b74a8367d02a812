"""The notebooks and examples use the public API only: every ``omtp_drake`` import they
make is ``from omtp_drake import NAME`` with NAME in ``omtp_drake.__all__`` (what a
student copies from them survives the next refactor); every public name is documented."""

import ast
import json
from pathlib import Path

import pytest

import omtp_drake

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
EXAMPLES = sorted((ROOT / "examples").rglob("*.py"))


def notebook_code(path: Path) -> str:
    """The code cells of a notebook, IPython's ``%`` and ``!`` lines left out."""
    cells = [c for c in json.loads(path.read_text())["cells"] if c["cell_type"] == "code"]
    lines = [ln for c in cells for ln in "".join(c["source"]).splitlines()]
    return "\n".join(ln for ln in lines if not ln.lstrip().startswith(("%", "!")))


def private_imports(code: str) -> list[str]:
    """The imports of ``omtp_drake`` in ``code`` that are not of a public name."""
    found = []
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Import):
            found += [f"import {a.name}" for a in node.names if a.name.startswith("omtp_drake.")]
        elif isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "omtp_drake":
            names = [a.name for a in node.names]
            if node.module != "omtp_drake" or not set(names) <= set(omtp_drake.__all__):
                found.append(f"from {node.module} import {', '.join(names)}")
    return found


def test_the_check_finds_an_internal_import():
    code = "import omtp_drake\nfrom omtp_drake import Cell\nfrom omtp_drake.sim.tf import TfBuffer\n"
    assert private_imports(code) == ["from omtp_drake.sim.tf import TfBuffer"]
    assert private_imports("import omtp_drake.viz.tree\nfrom omtp_drake import _LAZY") == [
        "import omtp_drake.viz.tree",
        "from omtp_drake import _LAZY",
    ]


@pytest.mark.parametrize("path", NOTEBOOKS + EXAMPLES, ids=lambda p: str(p.relative_to(ROOT)))
def test_notebooks_and_examples_import_public_names_only(path):
    code = notebook_code(path) if path.suffix == ".ipynb" else path.read_text()
    assert private_imports(code) == []


def test_every_public_name_resolves_and_is_documented():
    readme = (ROOT / "README.md").read_text()
    for name in omtp_drake.__all__:
        value = getattr(omtp_drake, name)
        assert (value.__doc__ or "").strip(), name
        assert f"`{name}`" in readme, f"{name} is not in the README's list of the public API"
    assert set(dir(omtp_drake)) >= set(omtp_drake.__all__)
