"""Composition over a repertoire: the composed switcher choosing among the
best elites of a quality-diversity kick run, get-up and return-legs; the
paper's three-behaviour composition unchanged."""

import numpy as np
import pytest

from helpers import assert_same_run, run_cli
from locustjump import rundir
from locustjump.evo import MapElitesParams, RCGAParams
from locustjump.rundir import FrozenGenomes
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.controller import MLP
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks import Composed, ComposedRepertoire, get_behaviour
from locustjump.tasks.composed import SIMPLE, SwitchingController
from locustjump.tasks.repertoire import RepertoireOptions

pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")

NET = MLP()


def test_a_switcher_over_n_networks_picks_its_largest_output(rng):
    nets = NET.random_genomes(rng, 5)
    ctl = SwitchingController(nets, networks=5)
    assert ctl.switcher.n_out == 5 and ctl.num_params == 10 * 10 + 5 * 11
    g = np.zeros((3, ctl.num_params))
    g[np.arange(3), ctl.num_params - 5 + np.array([4, 0, 3])] = 5.0  # output bias
    obs = rng.uniform(-1, 1, size=(3, 9))
    deltas, mem = ctl.act(ctl.prepare(g), np.zeros((3, 1)), obs, np.zeros((3, 4)), 0)
    np.testing.assert_array_equal(mem[:, 0], [4, 0, 3])
    for row, chosen in enumerate([4, 0, 3]):  # each row runs its pick, bit for bit
        alone = NET.forward(nets[chosen : chosen + 1], obs[row : row + 1])[0]
        np.testing.assert_array_equal(deltas[row], alone)
    with pytest.raises(ValueError, match="shape"):
        SwitchingController(nets, networks=4)


def test_the_papers_composition_is_the_three_simple_networks_still():
    assert Composed.frozen_names(Composed.Options()) == SIMPLE
    assert Composed.frozen_elites() == {}
    ctl = get_behaviour("composed", np.zeros((3, NET.num_params))).controller
    assert ctl.networks == 3 and ctl.num_params == 133


def test_a_repertoire_composition_takes_k_elites_then_getup_and_return_legs():
    opts = RepertoireOptions(elites=3)
    names = ComposedRepertoire.frozen_names(opts)
    assert names == ("kick", "kick", "kick", "getup", "return-legs")
    beh = get_behaviour("composed-repertoire", np.zeros((5, NET.num_params)), opts)
    assert beh.memory_labels == (
        "kick elite 0", "kick elite 1", "kick elite 2", "getup", "return-legs"
    )  # fmt: skip
    assert beh.terrains == Terrains() and beh.scene.is_flat
    assert beh.controller.networks == 5
    with pytest.raises(ValueError, match="needs 5 frozen genomes"):
        get_behaviour("composed-repertoire", np.zeros((3, 144)), opts).controller  # noqa: B018
    with pytest.raises(ValueError, match=r"^elites must be an integer in \[1, 64\]"):
        RepertoireOptions(elites=0)


def test_a_repertoire_composition_is_scored_on_its_terrains():
    t = Terrains(Debris(seed=3), count=2)
    beh = get_behaviour("composed-repertoire", np.zeros((5, NET.num_params)),
                        RepertoireOptions(elites=3), terrains=t)  # fmt: skip
    assert beh.terrains is t and beh.scene == Debris(seed=3)
    assert [s.seed for s in beh.terrains.scenes] == [3, 4]


@pytest.fixture(scope="module")
def sources(tmp_path_factory):
    """A small kick repertoire (MAP-Elites) and a plain (RCGA) kick run."""
    root = tmp_path_factory.mktemp("sources")
    qd = TrainConfig(generations=2, seed=1, optimizer=MapElitesParams(population=8))
    train(qd, root / "qd", progress=False)
    ga = TrainConfig(generations=1, optimizer=RCGAParams(population=4))
    train(ga, root / "ga", progress=False)
    return root


def two_elites(root, params, rng):
    """The frozen genomes of a composition over the 2 best elites of the
    repertoire ``root/qd``, with random get-up and return-legs networks."""
    kick = FrozenGenomes.from_runs(
        ("kick",), {"kick": root / "qd"}, params, 144, {"kick": 2}
    )
    return FrozenGenomes(
        ComposedRepertoire.frozen_names(RepertoireOptions(elites=2)),
        np.concatenate([kick.genomes, NET.random_genomes(rng, 2)]),
        (*kick.sources, "g", "r"),
        (*kick.hashes, "0", "0"),
    )


def composition(generations):
    """A small composition over 2 elites, trained by a population of 3."""
    return TrainConfig(
        behaviour="composed-repertoire",
        generations=generations,
        optimizer=RCGAParams(population=3, elite=1),
        options=RepertoireOptions(elites=2, switch_every=50),
    )


def test_the_frozen_genomes_are_the_archives_best_elites_in_order(sources, params):
    root = sources
    cfg = rundir.load_config(root / "qd" / rundir.CONFIG)
    a = rundir.read_archive(root / "qd", cfg, NET.num_params)
    dirs = {"kick": root / "qd", "getup": root / "ga", "return-legs": root / "ga"}
    # a kick run stands in for getup and return-legs here: only names differ
    with pytest.raises(Exception, match="holds a 'kick' run, not 'getup'"):
        FrozenGenomes.from_runs(SIMPLE, dirs, params, 144, {"kick": 2})
    dirs = {"kick": root / "qd"}
    f = FrozenGenomes.from_runs(("kick",), dirs, params, 144, {"kick": 2})
    assert f.behaviours == ("kick", "kick")
    np.testing.assert_array_equal(f.genomes, a.solution[a.ranked()[:2]])
    r = run_cli("train", "composed-repertoire", "--kick", str(root / "ga"),
                "--getup", str(root / "ga"), "--return-legs", str(root / "ga"),
                "--out", str(root / "x"))  # fmt: skip
    assert r.returncode == 2 and "a rcga run; the composition takes 8 elites" in (
        r.stderr
    )
    with pytest.raises(Exception, match=f"holds {len(a)} elites; the composition"):
        FrozenGenomes.from_runs(("kick",), dirs, params, 144, {"kick": len(a) + 1})


def test_a_repertoire_composition_trains_and_resumes_bit_for_bit(
    sources, params, tmp_path, rng
):
    root = sources
    frozen = two_elites(root, params, rng)
    cfg = composition(generations=2)
    train(cfg, tmp_path / "a", progress=False, frozen=frozen, stop_after=1)
    train(cfg, tmp_path / "a", progress=False, resume=True)
    train(cfg, tmp_path / "b", progress=False, frozen=frozen)
    assert_same_run(tmp_path / "a", tmp_path / "b")
    ev = run_cli("evaluate", str(tmp_path / "a"), "--json")
    assert ev.returncode == 0 and '"fitness_matches": true' in ev.stdout
    assert '"kick elite 1"' in ev.stdout  # its steps under each network


def test_the_repertoire_figure_marks_the_chosen_elites_and_checks_its_runs(
    sources, params, tmp_path, rng, capsys
):
    from pathlib import Path

    root = sources
    frozen = two_elites(root, params, rng)
    cfg = composition(generations=1)
    train(cfg, tmp_path / "c", progress=False, frozen=frozen)
    import importlib.util

    path = Path(__file__).resolve().parent.parent / "scripts" / "repertoire_figure.py"
    spec = importlib.util.spec_from_file_location("repertoire_figure", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)

    def figure(*args):
        code = script.main([str(a) for a in args])
        err = capsys.readouterr().err
        return code, err

    png = tmp_path / "r.png"
    code, err = figure(root / "qd", tmp_path / "c", "--out", png)
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    before = png.read_bytes()
    code, err = figure(root / "qd", tmp_path / "c", "--out", png)
    assert code == 2 and "exists (give --force" in err
    assert png.read_bytes() == before
    # a kick run that keeps no archive, and a run that composes none
    other = tmp_path / "o.png"
    code, err = figure(root / "ga", tmp_path / "c", "--out", other)
    assert code == 2 and err.count("\n") == 1, err
    assert "keeps no archive of elites" in err
    code, err = figure(root / "qd", root / "ga", "--out", other)
    assert code == 2 and "a kick run, not a composition over a" in err
    assert not other.exists()


def test_the_repertoire_figure_refuses_a_composition_of_other_elites(
    sources, params, tmp_path, rng
):
    from locustjump.errors import UserError
    from locustjump.present.repertoire import composition_figure

    frozen = FrozenGenomes(
        ComposedRepertoire.frozen_names(RepertoireOptions(elites=2)),
        NET.random_genomes(rng, 4),
        ("a", "b", "g", "r"),
        ("0", "0", "0", "0"),
    )
    cfg = composition(generations=1)
    train(cfg, tmp_path / "c", progress=False, frozen=frozen)
    message = "its 2 kick networks are not the 2 best elites of"
    with pytest.raises(UserError, match=message):
        composition_figure(sources / "qd", tmp_path / "c", tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()
