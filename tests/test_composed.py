"""Behaviour Composed: the switcher, composed runs and their bad input."""

from pathlib import Path

import numpy as np
import pytest

from locustjump import rundir
from locustjump.cli import main
from locustjump.errors import UserError
from locustjump.evo.rcga import RCGAParams
from locustjump.present.evaluate import evaluate_run
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.controller import MLP
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.tasks import SIMPLE_BEHAVIOURS, get_behaviour
from locustjump.tasks.composed import (
    SIMPLE,
    SWITCH_EVERY,
    SwitchingController,
    SwitchOptions,
    overturns,
)

NET, SWITCH = MLP(), MLP(n_out=3, output="sigmoid")


def switcher_choosing(index: np.ndarray | int, n: int = 1) -> np.ndarray:
    """Switcher genomes whose largest output is ``index`` whatever the input."""
    g = np.zeros((n, SWITCH.num_params))
    g[np.arange(n), SWITCH.num_params - 3 + np.asarray(index)] = 5.0  # output bias
    return g


def test_switcher_picks_the_largest_output_and_holds_it(rng):
    simple = NET.random_genomes(rng, 3)
    ctl = SwitchingController(simple)
    assert ctl.num_params == 133 and ctl.memory_size == 1
    obs = rng.uniform(-1, 1, size=(3, 9))
    prep = ctl.prepare(switcher_choosing([2, 0, 1], 3))
    deltas, mem = ctl.act(prep, np.zeros((3, 1)), obs, np.zeros((3, 4)), 0)
    np.testing.assert_array_equal(mem[:, 0], [2, 0, 1])
    # each row runs its selected frozen network, bit for bit as on its own
    for row, chosen in enumerate([2, 0, 1]):
        alone = NET.forward(simple[chosen : chosen + 1], obs[row : row + 1])[0]
        np.testing.assert_array_equal(deltas[row], alone)
    # between switches the memory, not the switcher, decides
    held = np.array([[1.0], [1.0], [1.0]])
    _, mem = ctl.act(prep, held, obs, np.zeros((3, 4)), SWITCH_EVERY - 1)
    np.testing.assert_array_equal(mem, held)
    _, mem = ctl.act(prep, held, obs, np.zeros((3, 4)), SWITCH_EVERY)
    np.testing.assert_array_equal(mem[:, 0], [2, 0, 1])


def test_switching_controller_rejects_wrong_simple_genomes():
    with pytest.raises(ValueError, match="shape"):
        SwitchingController(np.zeros((2, 144)))
    with pytest.raises(ValueError, match="three simple"):
        get_behaviour("composed").controller  # noqa: B018


def test_composed_rollout_same_on_any_threads_and_switches_every_120(params):
    # switchers (seeded) whose episodes do switch: episode 0 every decision
    rng = np.random.default_rng(0)
    beh = get_behaviour("composed", NET.random_genomes(rng, 3))
    g = SWITCH.random_genomes(rng, 4, scale=2.0)
    a = beh.simulate(g, params, record=("qpos", "memory"), backend=ThreadBackend(1))
    b = beh.simulate(g, params, record=("qpos", "memory"), backend=ThreadBackend(2))
    for k in ("qpos", "memory"):
        np.testing.assert_array_equal(a[k], b[k])
    sel = a["memory"][:, 1:, 0]  # the selection in force during step t
    changes = [np.flatnonzero(np.diff(s) != 0) + 1 for s in sel]
    assert sum(c.size > 0 for c in changes) >= 2  # the episodes do switch ...
    assert changes[0].size == 3000 // SWITCH_EVERY - 1  # (at every decision)
    for c in changes:  # ... and only at a decision, every 120 steps
        assert np.all(c % SWITCH_EVERY == 0), c
    assert set(np.unique(sel)) == {0.0, 1.0, 2.0}
    f = beh.fitness(a, params)
    np.testing.assert_allclose(f, a["qpos"][:, 1:, 2].sum(axis=1))


def test_switch_every_option_sets_when_the_switcher_decides(params):
    rng = np.random.default_rng(0)
    simple = NET.random_genomes(rng, 3)
    g = SWITCH.random_genomes(rng, 4, scale=2.0)
    beh = get_behaviour("composed", simple, SwitchOptions(switch_every=7))
    sel = beh.simulate(g, params, record=("memory",))["memory"][:, 1:, 0]
    changes = np.concatenate([np.flatnonzero(np.diff(s) != 0) + 1 for s in sel])
    assert changes.size > 0 and np.all(changes % 7 == 0)
    assert np.any(changes % SWITCH_EVERY != 0)  # not the default's decisions


def test_overturns_counts_falls_and_recoveries():
    uz = np.array([1.0, 0.95, -0.5, -0.9, 0.2, 0.95, 1.0, -0.1, 0.5])
    assert overturns(uz) == (2, 1)
    assert overturns(np.array([-1.0, -1.0, 0.95])) == (0, 0)  # started overturned


# --- composed runs -------------------------------------------------------------


@pytest.fixture(scope="module")
def simple_runs(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("simple")
    dirs = {}
    for name in SIMPLE:
        cfg = TrainConfig(
            behaviour=name, generations=1, optimizer=RCGAParams(population=4)
        )
        train(cfg, root / name, progress=False)
        dirs[name] = root / name
    return dirs


def test_composed_run_keeps_its_frozen_genomes(simple_runs, tmp_path):
    cfg = TrainConfig(
        behaviour="composed", generations=2, optimizer=RCGAParams(population=4)
    )
    simple = rundir.FrozenGenomes.from_runs(SIMPLE_BEHAVIOURS, simple_runs, cfg.model)
    out = tmp_path / "c"
    train(cfg.replace(generations=1), out, progress=False, frozen=simple)
    stored = rundir.load_config(out / rundir.CONFIG)
    assert stored.frozen_digest == simple.digest
    np.testing.assert_array_equal(
        rundir.FrozenGenomes.load(out / rundir.FROZEN, SIMPLE_BEHAVIOURS, 144).genomes,
        simple.genomes,
    )
    # resume needs nothing but the directory, and equals an uninterrupted run
    train(cfg, out, progress=False, resume=True)
    whole = tmp_path / "whole"
    train(cfg, whole, progress=False, frozen=simple)
    for name in (rundir.BEST, rundir.CHECKPOINT):
        with np.load(out / name) as a, np.load(whole / name) as b:
            for k in set(a.files) - {"metrics_row"}:  # holds the wall time
                np.testing.assert_array_equal(a[k], b[k], err_msg=f"{name}:{k}")
    ev = evaluate_run(out)
    assert ev.matches and (out / "eval" / "composed.png").is_file()
    assert set(ev.metrics["selected_steps"]) == set(SIMPLE)


def test_composed_bad_input(simple_runs, tmp_path, capsys):
    swapped = {**simple_runs, "kick": simple_runs["getup"]}
    argv = ["train", "composed", "--generations", "1", "--population", "4"]
    dirs = [f"--{k}={v}" for k, v in swapped.items()]
    assert main([*argv, *dirs, "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "holds a 'getup' run, not 'kick'" in err
    assert str(simple_runs["getup"]) in err
    assert not (tmp_path / "a").exists()
    # missing a simple run
    assert (
        main([*argv, f"--kick={simple_runs['kick']}", "--out", str(tmp_path / "b")])
        == 2
    )
    assert "--getup" in capsys.readouterr().err
    # --kick on a simple behaviour
    assert (
        main(
            [
                "train",
                "kick",
                f"--kick={simple_runs['kick']}",
                "--out",
                str(tmp_path / "c"),
            ]
        )
        == 2
    )
    assert "only for train composed" in capsys.readouterr().err
    # how the creature is computed may differ (engine, substeps), not which
    cfg = TrainConfig(behaviour="composed")
    finer = cfg.model.__class__(substeps=6)
    rundir.FrozenGenomes.from_runs(SIMPLE_BEHAVIOURS, simple_runs, finer)
    # different model parameters
    with pytest.raises(UserError, match="model parameters differ"):
        cfg = TrainConfig(behaviour="composed")
        rundir.FrozenGenomes.from_runs(
            SIMPLE_BEHAVIOURS,
            simple_runs,
            cfg.model.__class__(scale=2.0 * cfg.model.scale),
        )
    # a tampered simple.npz is refused on resume
    ok = [f"--{k}={v}" for k, v in simple_runs.items()]
    out = tmp_path / "d"
    assert main([*argv, *ok, "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    s = rundir.FrozenGenomes.load(out / rundir.FROZEN, SIMPLE_BEHAVIOURS, 144)
    rundir.FrozenGenomes(SIMPLE_BEHAVIOURS, s.genomes + 1.0, s.sources, s.hashes).save(
        out / rundir.FROZEN
    )
    before = (out / rundir.CHECKPOINT).read_bytes()
    assert (
        main(["train", "composed", "--generations", "2", "--resume", "--out", str(out)])
        == 2
    )
    assert "are not the ones" in capsys.readouterr().err
    assert (out / rundir.CHECKPOINT).read_bytes() == before


def test_switch_every_option_and_kick_variants(simple_runs, tmp_path, capsys, params):
    """--switch-every (beyond the paper) is recorded in config.toml, changes
    the hash, switches at its multiples and must match on resume; default
    configs keep their hash; a kick-apex run serves as the kick."""
    apex = tmp_path / "apex"
    train(
        TrainConfig("kick-apex", 0, 1, RCGAParams(population=4)), apex, progress=False
    )
    dirs = [f"--{k}={v}" for k, v in {**simple_runs, "kick": apex}.items()]
    argv = ["train", "composed", "--generations", "1", "--population", "4", "--quiet"]
    out = tmp_path / "c"
    assert main([*argv, *dirs, "--switch-every", "7", "--out", str(out)]) == 0
    cfg = rundir.load_config(out / rundir.CONFIG)
    assert cfg.options.switch_every == 7
    text = (out / rundir.CONFIG).read_text()
    assert "[options]\n" in text and "\nswitch_every = 7\n" in text
    assert cfg.hash() != cfg.replace(options=type(cfg.options)()).hash()
    _, beh, best = rundir.load_run(out)
    res = beh.simulate(best.genome[None], params, record=("memory",))
    sel = res["memory"][0, 1:, 0]
    assert np.all((np.flatnonzero(np.diff(sel)) + 1) % 7 == 0)
    assert evaluate_run(out).matches
    capsys.readouterr()
    resume = ["train", "composed", "--resume", "--out", str(out)]
    assert main([*resume, "--switch-every", "8"]) == 2
    assert "options.switch_every 8 differs" in capsys.readouterr().err
    assert (
        main(["train", "kick", "--switch-every", "8", "--out", str(tmp_path / "k")])
        == 2
    )
    assert (
        "only the composed, composed-height and composed-repertoire behaviours "
        "take it, not"
    ) in (capsys.readouterr().err)
    assert not (tmp_path / "k").exists()
    # the shipped composed runs (no [options]) read the paper's 120, same hash
    for r in ("quick-seed0", "paper-seed0"):
        d = Path(__file__).parent.parent / "results" / r / "composed"
        shipped = rundir.load_config(d / rundir.CONFIG)
        assert shipped.options.switch_every == SWITCH_EVERY
        assert f"config hash {shipped.hash()}" in (d / rundir.CONFIG).read_text()
