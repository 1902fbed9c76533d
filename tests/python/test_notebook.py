"""tests/python/test_notebook.py — examples/variants.ipynb runs headless (nbclient, the python3
kernel) in the test's own folder: no cell fails, it shows its grid and its plot, and the grid it
saved holds three by three images."""
import base64
import io
import os

import nbformat
from nbclient import NotebookClient
from PIL import Image

from conftest import SOURCE


def test_the_variants_notebook_runs(tmp_path):
    nb = nbformat.read(os.path.join(SOURCE, "examples", "variants.ipynb"), as_version=4)
    os.environ.setdefault("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    pngs = [o["data"]["image/png"] for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
            if "image/png" in o.get("data", {})]
    assert len(pngs) == 2, "the grid and the plot are shown"
    for p in pngs:
        img = Image.open(io.BytesIO(base64.b64decode(p)))
        assert img.width > 300 and img.height > 150
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    assert text.count("intensity") >= 9 and "mean |diff| 0.0000" in text  # the preset's own values: no difference
    grid = Image.open(tmp_path / "variants_grid.png").convert("RGB")
    assert grid.size == (720, 432)
    assert (tmp_path / "variants_plot.png").exists()
