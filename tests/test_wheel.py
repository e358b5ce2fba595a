"""The package as a user installs it without a clone: a wheel built from this
tree (pip's isolated build, as ``python -m build`` does) holds every module
and ``py.typed``, and the command line runs from it."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_a_built_wheel_installs_and_runs(tmp_path):
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
         "--wheel-dir", str(tmp_path / "dist"), str(ROOT)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    (wheel,) = (tmp_path / "dist").glob("locustjump-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    sources = {
        p.relative_to(ROOT / "src").as_posix()
        for p in (ROOT / "src" / "locustjump").rglob("*.py")
    }
    assert sources <= names, sorted(sources - names)[:5]
    assert "locustjump/py.typed" in names
    assert not any(n.startswith(("tests/", "results/")) for n in names)
    site = tmp_path / "site"
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
         "--target", str(site), str(wheel)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    env = {**os.environ, "PYTHONPATH": str(site)}  # ahead of the editable install
    out = subprocess.run(
        [sys.executable, "-c",
         "import locustjump, locustjump.cli as c; print(locustjump.__file__);"
         "c.main(['model', '--out', 'm.xml'])"],
        env=env, cwd=tmp_path, capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[0].startswith(str(site))
    assert "<mujoco" in (tmp_path / "m.xml").read_text()
