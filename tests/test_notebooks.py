"""Every notebook in notebooks/ executes headless (nbclient), about a minute each at most."""

from __future__ import annotations

from pathlib import Path

import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_executes(path: Path) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
    )
    client.execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors
    # a notebook that draws shows its figures (no non-interactive backend switched on before plt.show())
    if "matplotlib.pyplot" in "".join(c.source for c in nb.cells if c.cell_type == "code"):
        figures = [o for c in nb.cells for o in c.get("outputs", []) if "image/png" in o.get("data", {})]
        assert figures, f"{path.name} shows no figure"
