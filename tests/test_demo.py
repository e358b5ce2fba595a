"""`make demo` makes the shipped results/demo-seed0 (issue #33): the Makefile
runs the command its reproduce.toml records, on the default engine, and the
demo budget trains what it holds — the first generations of the kick, and of
the composed stage on its shipped frozen simple behaviours, row for row. The
same holds of the quick budget's shipped run on the default engine,
results/quick-seed0-numba."""

import csv
import re
from pathlib import Path

import pytest

from locustjump import rundir
from locustjump.runs.reproduction import BUDGETS, Reproduction
from locustjump.runs.trainer import train
from locustjump.sim.engine.job import DEFAULT_ENGINE
from locustjump.sim.engine.threads import ThreadBackend
from locustjump.tasks import behaviour_class

ROOT = Path(__file__).resolve().parent.parent
DEMO = ROOT / "results" / "demo-seed0"
#: shipped reproductions on the default engine: directory -> budget
SHIPPED = {DEMO: "demo", ROOT / "results" / "quick-seed0-numba": "quick"}
#: metrics.csv columns that are wall time, not the result
WALL = ("wall_s", "steps_per_s")


def _marker(run: Path) -> dict:
    if not (run / rundir.MARKER).is_file():
        pytest.skip(f"{run} not present")
    return rundir.read_toml(run / rundir.MARKER)


@pytest.fixture(scope="module")
def marker() -> dict:
    return _marker(DEMO)


def test_make_demo_runs_the_command_the_shipped_demo_records(marker):
    demo = re.search(r"^demo:.*?(?=^\S)", (ROOT / "Makefile").read_text(), re.M | re.S)
    ran = [ln.split("/locustjump ", 1)[1] for ln in demo.group(0).splitlines()
           if "/locustjump reproduce " in ln]  # fmt: skip
    assert ran == [
        marker["command"]
        .removeprefix("locustjump ")
        .replace("--out results/demo-seed0", "--out demo/reproduce")
    ]
    assert marker["engine"] == DEFAULT_ENGINE and marker["budget"] == "demo"
    budget = BUDGETS["demo"]
    assert marker["generations"] == budget.generations
    assert marker["population"] == budget.population


def _rows(path: Path, n: int) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))[:n]
    return [{k: v for k, v in r.items() if k not in WALL} for r in rows]


@pytest.mark.parametrize("run", list(SHIPPED), ids=lambda p: p.name)
@pytest.mark.parametrize("stage, generations", [("kick", 2), ("composed", 1)])
def test_the_budget_trains_what_the_shipped_run_holds(
    run, tmp_path, stage, generations
):
    """The budget's configuration of ``stage`` on the default engine is the
    shipped one, and training it (from the shipped frozen genomes where it
    builds on some) repeats the shipped metrics.csv's first rows (wall-time
    columns aside)."""
    marker = _marker(run)
    assert marker["engine"] == DEFAULT_ENGINE and marker["budget"] == SHIPPED[run]
    rep = Reproduction.open(tmp_path / "r", SHIPPED[run], (marker["seed"],))
    cfg = rep.train_config(stage)
    shipped = rundir.load_config(run / stage / rundir.CONFIG)
    needs = behaviour_class(stage).requires
    frozen = None
    if needs:
        dirs = {s: run / s for s in needs}
        frozen = rundir.FrozenGenomes.from_runs(needs, dirs, cfg.model)
        cfg = cfg.replace(frozen_digest=frozen.digest)
    assert cfg == shipped
    out = tmp_path / stage
    train(cfg.replace(generations=generations), out, progress=False,
          frozen=frozen, backend=ThreadBackend(2))  # fmt: skip
    mine = _rows(out / rundir.METRICS, generations)
    assert len(mine) == generations
    assert mine == _rows(run / stage / rundir.METRICS, generations)
