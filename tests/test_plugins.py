"""Plugins (issue #47): a package installed beside locustjump adds an
optimizer, a behaviour (with an option of its own) and a scene through entry
points, or a module given with --plugin; the command line trains with them,
and evaluates, reports, compares, renders and resumes their runs like any
other; without the plugin, a run made with it fails in one line naming it;
a broken plugin is named in one line and skipped.

The plugin is tests/plugin/tinyplug, "installed" by copying it into a
directory on the path beside a ``*.dist-info`` holding its entry points, as
pip leaves an installed distribution."""

import importlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import locustjump
from helpers import run_cli
from locustjump import evo, plugins, rundir, tasks
from locustjump.sim import scene

PLUGIN = Path(__file__).resolve().parent / "plugin" / "tinyplug"
SRC = Path(locustjump.__file__).resolve().parents[1]
ENTRY_POINTS = """\
[locustjump.optimizers]
hillclimb = tinyplug.hill:HillClimb

[locustjump.tasks]
stand-tall = tinyplug.stand

[locustjump.scenes]
slab = tinyplug.slab:Slab
"""
BROKEN = "[locustjump.optimizers]\nnothere = tinybroken.nope:Thing\n"


def _install(site: Path, name: str = "tinyplug", entry_points: str | None = None):
    """``name`` as pip would leave it in ``site``: the package (tinyplug's),
    and with ``entry_points`` its distribution's metadata."""
    site.mkdir(parents=True, exist_ok=True)
    if name == "tinyplug":
        shutil.copytree(PLUGIN, site / name)
    if entry_points is not None:
        info = site / f"{name}-0.1.dist-info"
        info.mkdir()
        metadata = f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.1\n"
        (info / "METADATA").write_text(metadata)
        (info / "entry_points.txt").write_text(entry_points)
        (info / "top_level.txt").write_text(f"{name}\n")
    importlib.invalidate_caches()
    return site


def _cli(sites: list[Path], *argv: str, cwd: Path) -> subprocess.CompletedProcess:
    """``locustjump ARGV`` in a fresh process with ``sites`` on its path."""
    path = os.pathsep.join([*map(str, sites), str(SRC)])
    return subprocess.run(
        [sys.executable, "-m", "locustjump.cli", *argv],
        cwd=cwd, env={**os.environ, "PYTHONPATH": path},
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip


def _forget_tinyplug() -> None:
    for name in [m for m in sys.modules if m.split(".")[0] == "tinyplug"]:
        del sys.modules[name]


@pytest.fixture
def fresh(monkeypatch):
    """``fresh()``: this process's registries and plugin loader as a new
    process has them (nothing of tinyplug loaded); all restored after."""
    registries = {m: dict(m._REGISTRY) for m in (evo, tasks, scene)}

    def forget() -> None:
        for module, registry in registries.items():
            monkeypatch.setattr(module, "_REGISTRY", dict(registry))
        monkeypatch.setattr(plugins, "_loaded", set())
        monkeypatch.setattr(plugins, "_distributions", {})
        _forget_tinyplug()

    forget()
    yield forget
    _forget_tinyplug()


def test_an_installed_plugin_is_used_like_any_part(tmp_path, fresh, monkeypatch):
    site = _install(tmp_path / "site", entry_points=ENTRY_POINTS)
    broken = _install(tmp_path / "broken", "tinybroken", BROKEN)
    run = tmp_path / "run"
    # a fresh process finds all three by their entry points: its optimizer
    # and behaviour are choices of train, its scene a --scene, the
    # behaviour's option a flag; a broken plugin beside it is named in one
    # line and skipped
    made = _cli([site, broken], "train", "stand-tall", "--optimizer", "hillclimb",
                "--scene", "slab", "--settle-steps", "10", "--generations", "2",
                "--population", "4", "--quiet", "--out", str(run),
                cwd=tmp_path)  # fmt: skip
    assert made.returncode == 0, made.stderr
    assert made.stderr == (
        "locustjump: warning: plugin 'nothere' of distribution tinybroken "
        "(tinybroken.nope:Thing in locustjump.optimizers) failed to load and is "
        "skipped: ModuleNotFoundError: No module named 'tinybroken'\n"
    )
    text = (run / rundir.CONFIG).read_text()
    assert '[optimizer]\nkind = "hillclimb"' in text and "settle_steps = 10" in text
    assert '[scene]\nkind = "slab"' in text
    assert '[plugins]\n"tinyplug.hill" = "tinyplug"\n' in text  # for the error
    for module in ("stand", "slab"):
        assert f'"tinyplug.{module}" = "tinyplug"\n' in text

    # not installed: every command that reads the run says so in one line
    missing = (
        f"locustjump: error: {run / rundir.CONFIG}: made with the plugin "
        "tinyplug.hill (distribution tinyplug), which is not loaded here: "
        "install tinyplug, or give --plugin tinyplug.hill\n"
    )
    for argv in (["evaluate", str(run)], ["report", str(run)],
                 ["compare", str(run)], ["render", str(run), "--fps", "2"],
                 ["train", "kick", "--resume", "--out", str(run)]):  # fmt: skip
        r = run_cli(*argv)
        assert (r.returncode, r.stderr) == (2, missing), argv
    assert not (run / rundir.EVAL).exists()

    # installed (here, in this process: found lazily when first asked for,
    # by the library as by the command line)
    monkeypatch.syspath_prepend(str(site))
    fresh()
    cfg = rundir.load_config(run / rundir.CONFIG)
    assert (cfg.optimizer.kind, cfg.behaviour, cfg.scene.scene.name) == (
        "hillclimb", "stand-tall", "slab"
    )  # fmt: skip
    fresh()
    r = run_cli("train", "stand-tall", "--resume", "--generations", "3", "--quiet",
                "--out", str(run))  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "stand-tall: 3 generations" in r.stdout
    r = run_cli("evaluate", str(run))
    assert r.returncode == 0 and "matches training" in r.stdout, r.stderr
    r = run_cli("report", str(run), "--out", str(tmp_path / "report.html"))
    assert r.returncode == 0 and (tmp_path / "report.html").is_file(), r.stderr
    r = run_cli("compare", str(run))
    assert r.returncode == 0 and "| hillclimb | 1 |" in r.stdout, r.stderr
    video = tmp_path / "v.gif"
    r = run_cli("render", str(run), "--out", str(video), "--fps", "2")
    if r.returncode == 2 and "cannot render offscreen" in r.stderr:
        pytest.skip(r.stderr)
    assert r.returncode == 0 and video.stat().st_size > 0, r.stderr


def test_a_plugin_module_given_by_name(tmp_path, fresh, monkeypatch):
    site = _install(tmp_path / "site")  # a package, no entry points
    monkeypatch.syspath_prepend(str(site))
    run = tmp_path / "run"
    argv = ["train", "kick", "--optimizer", "hillclimb", "--generations", "1",
            "--population", "4", "--quiet", "--out", str(run)]  # fmt: skip
    r = run_cli(*argv)
    assert r.returncode == 2 and "invalid choice: 'hillclimb'" in r.stderr
    r = run_cli(*argv, "--plugin", "tinyplug.hill")
    assert r.returncode == 0, r.stderr
    assert '[plugins]\n"tinyplug.hill" = ""\n' in (run / rundir.CONFIG).read_text()
    fresh()
    r = run_cli("evaluate", str(run))
    assert r.returncode == 2 and r.stderr.endswith(
        "made with the plugin tinyplug.hill, which is not loaded here: install "
        "it, or give --plugin tinyplug.hill\n"
    )
    r = run_cli("--plugin=tinyplug.hill", "evaluate", str(run))
    assert r.returncode == 0 and "matches training" in r.stdout, r.stderr
    for bad, error in [
        ("nosuch.mod", "--plugin nosuch.mod: cannot import it (ModuleNotFoundError: "
                       "No module named 'nosuch')"),
        ("../x", "--plugin: '../x' is not a module name (e.g. mypkg.mod)"),
    ]:  # fmt: skip
        r = run_cli("--plugin", bad, "evaluate", str(run))
        assert (r.returncode, r.stderr) == (2, f"locustjump: error: {error}\n")
    r = run_cli("evaluate", str(run), "--plugin")
    assert r.returncode == 2 and "--plugin: expected a module name" in r.stderr
