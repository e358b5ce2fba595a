"""The layer contract (pyproject.toml's [tool.importlinter]) holds, and it
would catch what it is there to catch: an upward import, an import cycle."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = Path(sys.executable).with_name("lint-imports")


def _lint(tmp_path: Path, edit: tuple[str, str] | None = None):
    """``lint-imports`` on a copy of the package, with one line appended to
    one module (``edit``: path under ``locustjump/``, the line)."""
    if not LINT.exists():
        pytest.skip("import-linter not installed (pip install -e '.[test]')")
    src = tmp_path / "src"
    shutil.copytree(ROOT / "src" / "locustjump", src / "locustjump",
                    ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    if edit is not None:
        module, line = edit
        with open(src / "locustjump" / module, "a") as f:
            f.write(f"\n{line}\n")
    return subprocess.run(
        [str(LINT), "--no-cache"],
        cwd=tmp_path,
        env={"PYTHONPATH": str(src), "PATH": "/usr/bin:/bin"},
        capture_output=True,
        text=True,
    )


def test_the_contracts_are_kept(tmp_path):
    r = _lint(tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "2 kept, 0 broken" in r.stdout


@pytest.mark.parametrize(
    "module, line",
    [
        ("sim/model.py", "from locustjump.present import plots"),  # sim -> present
        ("tasks/kick.py", "from locustjump.rundir import layout"),  # tasks -> rundir
        ("evo/rcga.py", "from locustjump.tasks import kick"),  # sibling layers
        ("rundir/files.py", "import locustjump.runs.trainer"),  # inside a function
    ],
)
def test_an_upward_import_breaks_the_layers(tmp_path, module, line):
    if line.startswith("import"):  # an import hidden in a function counts too
        line = f"def _later():\n    {line}"
    r = _lint(tmp_path, (module, line))
    assert r.returncode == 1
    assert "each layer imports only the layers below it BROKEN" in r.stdout


def test_an_import_cycle_breaks_the_acyclic_contract(tmp_path):
    # tasks.kick imports tasks.reference, which imports tasks.rules; rules
    # importing kick closes a cycle
    r = _lint(tmp_path, ("tasks/rules.py", "from locustjump.tasks import kick"))
    assert r.returncode == 1
    assert "no import cycle between the modules of any package BROKEN" in r.stdout
