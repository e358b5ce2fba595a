"""docs/tutorial.ipynb runs, top to bottom, on a small budget (so it cannot go
stale), and is what scripts/make_tutorial.py writes."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOK = ROOT / "docs" / "tutorial.ipynb"

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")


def _maker():
    spec = importlib.util.spec_from_file_location(
        "make_tutorial", ROOT / "scripts" / "make_tutorial.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_notebook_is_what_the_script_writes():
    on_disk = nbformat.read(NOTEBOOK, as_version=4)
    made = _maker().notebook()
    assert [c.source for c in on_disk.cells] == [c.source for c in made.cells]
    assert all(not c.get("outputs") for c in on_disk.cells if c.cell_type == "code")


def test_tutorial_runs(monkeypatch, tmp_path, render_problem):
    if render_problem is not None:  # it shows a frame of the evolved kick
        pytest.skip(f"no offscreen rendering here: {render_problem}")
    monkeypatch.setenv("LJ_TUTORIAL_GENERATIONS", "3")
    monkeypatch.setenv("LJ_TUTORIAL_POPULATION", "6")
    monkeypatch.delenv("MPLBACKEND", raising=False)  # the kernel's inline figures
    monkeypatch.setenv("TMPDIR", str(tmp_path))  # its runs land here
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3",
        resources={"metadata": {"path": str(ROOT / "docs")}},
    )  # fmt: skip
    client.execute()
    text = "\n".join(
        out.get("text", "")
        for cell in nb.cells if cell.cell_type == "code"
        for out in cell.get("outputs", [])
    )  # fmt: skip
    assert "best fitness" in text and "after 3 generations" in text
    assert "identical: True" in text  # the run replays bit for bit
    assert "composed switches among ('kick', 'getup', 'return-legs')" in text
    assert "a random policy's kick return" in text
    images = [
        out for cell in nb.cells if cell.cell_type == "code"
        for out in cell.get("outputs", []) if "image/png" in out.get("data", {})
    ]  # fmt: skip
    assert len(images) == 2  # the learning curve and the frame
    (work,) = tmp_path.glob("locustjump-tutorial-*")
    assert (work / "kick" / "best.npz").is_file()
    assert (work / "composed" / "frozen.npz").is_file()


def test_importing_the_figures_leaves_the_backend_alone():
    """A notebook's inline figures need the user's backend: the library draws
    on ``Figure`` objects and never calls ``matplotlib.use``."""
    import os
    import subprocess

    code = (
        "import locustjump.present.plots, locustjump.present.compare, matplotlib;"
        "print(matplotlib.get_backend())"
    )
    env = {**os.environ, "MPLBACKEND": "template"}
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True,
        check=True,
    )  # fmt: skip
    assert out.stdout.strip() == "template"
