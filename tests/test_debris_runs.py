"""Training on debris: several terrains, unseen ones, the commands that take
a scene, a reproduction and its report on debris."""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest

from helpers import TINY_GENERATIONS, run_cli
from locustjump import rundir
from locustjump.cli.resolve import terrains_arg
from locustjump.errors import UserError
from locustjump.present import report
from locustjump.rundir.config import TrainConfig
from locustjump.runs import reproduction
from locustjump.runs.reproduce import Budget, reproduce
from locustjump.sim import model as lm
from locustjump.sim.scene import Debris, Flat, Terrains
from locustjump.tasks import get_behaviour

P = lm.LocustParams()


def test_several_terrains_score_the_mean_or_the_worst():
    t = Terrains(Debris(seed=7), 2)
    assert [s.seed for s in t.scenes] == [7, 8]
    beh = get_behaviour("kick", terrains=t)
    g = beh.controller.random_genomes(np.random.default_rng(0), 3, scale=1.0)
    fit, res = beh.evaluate(g, P)
    each = [beh.on(s).evaluate(g, P)[0] for s in t.scenes]
    np.testing.assert_array_equal(fit, (each[0] + each[1]) / 2)
    assert res.control_steps == 2 * 3 * beh.n_steps
    worst = get_behaviour("kick", terrains=Terrains(Debris(seed=7), 2, "min"))
    np.testing.assert_array_equal(worst.evaluate(g, P)[0], np.minimum(*each))
    with pytest.raises(ValueError, match="one terrain"):
        Terrains(Flat(), 2)


def test_scene_config_is_recorded_hashed_and_checked(tmp_path):
    assert TrainConfig().hash() == "1c1e0a431ebc3af3"  # flat runs keep theirs
    cfg = TrainConfig(scene=Terrains(Debris(seed=3, spacing=1.5), 4, "min"))
    d = cfg.to_dict()
    assert d["scene"]["kind"] == "debris" and d["scene"]["terrains"] == 4
    assert TrainConfig.from_dict(d, "x") == cfg
    assert cfg.hash() != TrainConfig().hash()
    assert (
        cfg.replace(scene=Terrains(Debris(seed=4, spacing=1.5), 4, "min")).hash()
        != cfg.hash()
    )
    for table, message in [
        ({"kind": "lava"}, "unknown scene 'lava'"),
        ({"kind": "debris", "bogus": 1}, "unknown key 'scene.bogus'"),
        ({"kind": "debris", "spacing": -1}, r"\[scene\] spacing"),
        ({"kind": "debris", "terrains": 0}, "terrains must be"),
        ({"kind": "debris", "seed": 2**64}, "seed"),
    ]:
        with pytest.raises(UserError, match=message):
            TrainConfig.from_dict({"scene": table}, "cfg.toml")


@pytest.fixture(scope="module")
def debris_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("debris") / "kick"
    r = run_cli(
        "train", "kick", "--scene", "debris", "--terrain-seed", "10", "--terrains",
        "2", "--population", "4", "--generations", "2", "--threads", "2",
        "--quiet", "--out", str(out),
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    return out


def test_training_on_debris_is_deterministic(debris_run, tmp_path):
    cfg = rundir.load_config(debris_run / rundir.CONFIG)
    assert cfg.scene == Terrains(Debris(seed=10), 2)
    other = tmp_path / "again"
    r = run_cli(
        "train", "kick", "--config", str(debris_run / rundir.CONFIG),
        "--threads", "1", "--quiet", "--out", str(other),
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    a = np.load(debris_run / rundir.BEST)
    b = np.load(other / rundir.BEST)
    np.testing.assert_array_equal(a["genome"], b["genome"])
    assert float(a["fitness"]) == float(b["fitness"])


def test_a_run_on_two_terrains_re_simulates_to_its_fitness(tmp_path):
    """Evaluated, a run's fitness is again the mean over its terrains; its
    figures are of the first (five get-up start states, not ten)."""
    out = tmp_path / "getup"
    r = run_cli(
        "train", "getup", "--scene", "debris", "--terrains", "2", "--population",
        "4", "--generations", "1", "--quiet", "--out", str(out),
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    r = run_cli("evaluate", str(out), "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["fitness_matches"]


def test_evaluate_on_unseen_terrains_prints_the_gap(debris_run):
    r = run_cli("evaluate", str(debris_run), "--terrain-seeds", "10-12", "--json")
    assert r.returncode == 0, r.stderr
    te = json.loads(r.stdout)
    assert [t["seed"] for t in te["terrains"]] == [10, 11, 12]
    assert [t["trained"] for t in te["terrains"]] == [True, True, False]
    trained = [t["fitness"] for t in te["terrains"][:2]]
    assert np.mean(trained) == te["train_fitness"]  # the recorded aggregate
    assert te["held_out_fitness"] == te["terrains"][2]["fitness"]
    assert te["generalisation_gap"] == te["train_fitness"] - te["held_out_fitness"]
    r = run_cli("evaluate", str(debris_run), "--terrain-seeds", "12")
    assert r.returncode == 0 and "generalisation gap" in r.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--terrain-seeds", "x"], "--terrain-seeds"),
        (["--scene", "lava"], "--scene: unknown scene 'lava'"),
        (["--scene", "flat", "--terrain-seed", "3"], "--terrain-seed"),
    ],
)
def test_bad_scene_options_are_one_line(debris_run, args, message):
    before = sorted(p.name for p in debris_run.rglob("*"))
    r = run_cli("evaluate", str(debris_run), *args)
    assert r.returncode == 2 and message in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert sorted(p.name for p in debris_run.rglob("*")) == before


def test_bad_scene_for_training_writes_nothing(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[scene]\nkind = "debris"\nspacing = 0.01\n')
    for args in (["--scene", str(bad)], ["--scene", "flat", "--terrains", "3"]):
        r = run_cli("train", "kick", *args, "--out", str(tmp_path / "run"))
        assert r.returncode == 2, r.stderr
        assert len(r.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "run").exists()


def test_model_and_rules_take_a_scene(tmp_path):
    r = run_cli("model", "--scene", "debris", "--terrain-seed", "2",
                "--out", str(tmp_path / "m.xml"))  # fmt: skip
    assert r.returncode == 0, r.stderr
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "m.xml"))
    assert m.ngeom == lm.load_model(P, Debris(seed=2)).ngeom
    r = run_cli("rules", "--scene", "debris", "--steps", "600", "--out",
                str(tmp_path / "rules"))  # fmt: skip
    assert r.returncode == 0, r.stderr
    summary = json.loads((tmp_path / "rules" / rundir.RULES_SUMMARY).read_text())
    assert summary["scene"]["kind"] == "debris" and "jumps_before_stuck" in summary


def test_a_reproduction_on_debris_reports_the_held_out_terrains(tmp_path, monkeypatch):
    """``reproduce --scene debris`` scores every stage's best genome on
    terrains training never saw; results.md (and so report.html) shows them."""
    monkeypatch.setattr(reproduction, "HELD_OUT_SEEDS", (100, 101))
    out = tmp_path / "r"
    reproduce(out, budget=Budget("tiny", 4, TINY_GENERATIONS), seed=0,
              progress=False, log=lambda s: None, videos=False, monolithic=False,
              terrains=Terrains(Debris(seed=5)))  # fmt: skip
    md = (out / rundir.RESULTS).read_text()
    section = md.split("## On terrains training never saw", 1)[1].split("\n## ", 1)[0]
    assert "debris terrains 100, 101" in section
    rows = [ln for ln in section.splitlines() if ln.startswith("| ")][2:]
    assert [r.split(" | ")[0] for r in rows] == [
        "| kick", "| getup", "| return-legs", "| composed",
    ]  # fmt: skip
    held = rundir.read_json(rundir.eval_metrics_path(out / "composed"))["held_out"]
    assert [t["seed"] for t in held["terrains"]] == [100, 101]
    assert held["train_fitness"] == rundir.load_run(out / "composed")[2].fitness
    assert held["held_out_fitness"] == np.mean([t["fitness"] for t in held["terrains"]])
    assert f"{held['held_out_fitness']:.4g}" in rows[3]
    html = (out / rundir.REPORT).read_text()
    assert "On terrains training never saw" in html


def test_the_report_of_a_debris_run_shows_the_held_out_table(
    debris_run, tmp_path, monkeypatch
):
    monkeypatch.setattr(report, "HELD_OUT_SEEDS", (11, 12))  # 11 trained on
    page = report.write_report(debris_run, out=tmp_path / "report.html")
    html = page.read_text()
    assert "On terrains training never saw" in html and "debris terrains 12" in html
    assert "<td>kick</td>" in html


def test_a_reproduction_on_debris_of_its_own_names_its_marker(tmp_path):
    """Its command remakes it: non-default debris parameters come from the
    [scene] table of its marker (``--scene FILE``), the default ones by name."""
    mine = Terrains(Debris(seed=2, height_max=0.3), 2, "min")
    rep = reproduction.Reproduction.open(tmp_path / "r", "quick", (0,), terrains=mine)
    rep.start(rep.command())
    marker = tmp_path / "r" / rundir.MARKER
    assert f" --scene {marker} " in rep.command()
    assert terrains_arg(str(marker)) == mine
    plain = reproduction.Reproduction.open(
        tmp_path / "p", "quick", (0,), terrains=Terrains(Debris(seed=2), 2)
    )
    assert " --scene debris --terrain-seed 2 --terrains 2 " in plain.command()
