"""The example notebook runs top to bottom in a real kernel (nbclient + ipykernel)."""

from __future__ import annotations

import base64
import io
from pathlib import Path

import pytest

nbclient = pytest.importorskip("nbclient")
nbformat = pytest.importorskip("nbformat")
pytest.importorskip("ipykernel")
pytest.importorskip("anywidget")

NOTEBOOK = Path(__file__).parents[2] / "examples" / "jupyter.ipynb"


def test_the_example_notebook_runs(tmp_path):
    import numpy as np
    from PIL import Image

    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError on the first failing cell
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    errors = [o for o in outputs if o.output_type == "error"]
    # the one refused value (a cell tagged raises-exception): its message, no traceback
    assert len(errors) == 1 and errors[0].ename == "SylvaError"
    assert errors[0].traceback == [
        "\x1b[31mSylvaError\x1b[0m: angle: expected a value in 0..45, got 1000"]
    assert not [o for o in outputs if o.get("name") == "stderr" and "Traceback" in o.text]
    pngs = [o.data["image/png"] for o in outputs if "image/png" in o.get("data", {})]
    assert len(pngs) >= 4  # the plant, its scene, the aspen and the world, inline
    for data in pngs:
        with Image.open(io.BytesIO(base64.b64decode(data))) as im:
            assert im.size[0] >= 100 and len(np.unique(np.asarray(im.convert("L")))) > 5
    scene_cell = next(c for c in nb.cells if c.source.startswith("plant.scene"))
    assert any("image/png" in o.get("data", {}) for o in scene_cell.outputs)
    views = [o for o in outputs if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(views) >= 3  # plant.show(), explore(...), aspen.show()
    saved = [o for o in outputs if "growth.gif" in str(o.get("data", {}).get("text/plain", ""))]
    assert saved
