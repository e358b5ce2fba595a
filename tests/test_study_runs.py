"""A study's runs (runs/study.py) stated exactly: how far each is and what it
costs, the checks that a run on disk is the one the study declares (its
configuration, its budget, the runs it builds on, the run it extends), and
what the composed arms are given. On tiny runs trained here (seconds);
``tests/test_study_cmd.py`` and ``tests/test_study_workers.py`` train
studies through the command and with several workers."""

import dataclasses
import shutil
from pathlib import Path

import pytest

from helpers import SIMPLE_ARMS, user_error
from locustjump import rundir
from locustjump.runs import study as S
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train
from locustjump.tasks import get_behaviour

TEXT = (
    """root = "{root}"
seeds = "0-1"
[defaults]
generations = 2
optimizer = {{ population = 4 }}
"""
    + SIMPLE_ARMS
    + """[arms.c]
behaviour = "composed"
generations = 1
frozen = {{ kick = "kick", getup = "getup", return-legs = "legs" }}
[evaluation]
terrain_seeds = "100-102"
substeps = [3, 12]
"""
)


def study_file(root: Path, text: str = TEXT, **changes: str) -> Path:
    for old, new in changes.items():
        assert old in text
        text = text.replace(old, new)
    path = root / "s.toml"
    path.write_text(text.format(root=root / "runs"))
    return path


def train_run(study, arm: str, seed: int, **kw) -> Path:
    a = study.arms[arm]
    frozen = S.frozen_genomes(study, a, seed) if a.frozen else None
    train(a.config(seed), a.run_dir(seed), progress=False, frozen=frozen, **kw)
    return a.run_dir(seed)


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """Seed 0 of the study, every arm trained (the composed arm too)."""
    root = tmp_path_factory.mktemp("study-runs")
    study = load_study(study_file(root))
    for arm in ("kick", "getup", "legs", "c"):
        train_run(study, arm, 0)
    return root, study


def copy_of(trained, tmp_path: Path, **changes: str):
    """The trained study under ``tmp_path`` (its runs copied), its file changed."""
    root, _ = trained
    shutil.copytree(root / "runs", tmp_path / "runs")
    return load_study(study_file(tmp_path, **changes))


def test_a_runs_state(tmp_path):
    st = S.RunState("a", 0, tmp_path, 0, 3, 10, 7)
    assert (st.finished, st.status, st.steps_left) == (False, "to do", 30)
    st = S.RunState("a", 0, tmp_path, 2, 3, 10, 7)
    assert (st.finished, st.status, st.steps_left) == (False, "2/3", 10)
    st = S.RunState("a", 0, tmp_path, 3, 3, 10, 7)
    assert (st.finished, st.status, st.steps_left) == (True, "done", 0)
    st = S.RunState("a", 0, tmp_path, 4, 3, 10, 7)
    assert (st.finished, st.status, st.steps_left) == (True, "done", 0)
    (tmp_path / rundir.STOP).write_text("{}")  # its optimizer stopped it early
    st = S.RunState("a", 0, tmp_path, 1, 3, 10, 7)
    assert (st.finished, st.status, st.steps_left) == (True, "done", 0)


def test_the_control_steps_of_a_genome_in_training_and_in_scoring(tmp_path):
    debris = '{{ kind = "debris", seed = 7, terrains = 2 }}'
    text = TEXT.replace("[arms.kick]", f"scene = {debris}\n[arms.kick]", 1)
    study = load_study(study_file(tmp_path, text))
    cfg = study.arms["kick"].config(0)
    kick = get_behaviour("kick")
    states = len(kick.start_states(cfg.model))
    assert S.episode_steps(cfg) == states * 2 * kick.n_steps == 600 * states
    twice = cfg.replace(
        options=dataclasses.replace(cfg.options, score_substeps=(6, 12))
    )
    assert S.episode_steps(twice) == 3 * S.episode_steps(cfg)
    one = states * kick.n_steps * 3  # on the 3 held-out terrains
    assert S.score_steps(study, cfg, kick) == {3: one, 12: one}
    beh = S.behaviour_for(twice)
    plain = load_study(study_file(tmp_path, text, **{"substeps = [3, 12]": ""}))
    assert S.score_steps(plain, twice, beh) == {None: 3 * one}  # re-simulated too
    own = load_study(study_file(tmp_path, text, **{'terrain_seeds = "100-102"': ""}))
    assert S.score_steps(own, cfg, kick) == {3: 2 * one // 3, 12: 2 * one // 3}


def test_a_composed_behaviour_for_its_episodes_alone(trained):
    _, study = trained
    beh = S.behaviour_for(study.arms["c"].config(0))
    assert beh.name == "composed" and beh.frozen.shape[0] == 3
    assert not beh.frozen.any()  # placeholders


def test_generations_done(trained, tmp_path):
    _, study = trained
    assert S.generations_done(study.arms["kick"].run_dir(0)) == 2
    assert S.generations_done(study.arms["c"].run_dir(0)) == 1
    assert S.generations_done(tmp_path / "none") == 0
    run = tmp_path / "run"
    shutil.copytree(study.arms["kick"].run_dir(0), run)
    (run / rundir.METRICS).unlink()
    assert S.generations_done(run) == 0
    (run / rundir.CONFIG).unlink()
    (run / rundir.METRICS).write_text("x")  # not a run: never read
    assert S.generations_done(run) == 0


def test_the_states_of_a_study(trained):
    _, study = trained
    got = {(s.arm, s.seed): s for s in S.states(study)}
    assert list(got) == [("kick", 0), ("getup", 5), ("legs", 0), ("c", 0),
                         ("kick", 1), ("legs", 1), ("c", 1)]  # fmt: skip
    assert [(s.done, s.generations) for s in got.values()] == [
        (2, 2), (2, 2), (2, 2), (1, 1), (0, 2), (0, 2), (0, 1)
    ]  # fmt: skip
    for (arm, seed), s in got.items():
        cfg = study.arms[arm].config(seed)
        assert s.path == study.arms[arm].run_dir(seed)
        assert s.steps_per_generation == 4 * S.episode_steps(cfg)
        beh = S.behaviour_for(cfg)
        scored = sum(S.score_steps(study, cfg, beh).values())
        assert s.eval_steps == (scored if arm == "c" else 0)
    assert got[("c", 0)].eval_steps > 0


def test_the_declared_runs_pass(trained):
    _, study = trained
    for arm, seed in study.runs():
        S.check_run(study, arm, seed)  # seed 1's: none yet, nothing to check


def test_a_run_of_another_configuration_names_each_key(trained, tmp_path):
    numpy = {"generations = 2\n": 'generations = 2\nengine = "numpy"\n'}
    study = copy_of(trained, tmp_path, **numpy)
    path = study.arms["kick"].run_dir(0)
    got = user_error(S.check_run, study, study.arms["kick"], 0)
    assert got == (
        f"{path}: not the run {study.source} declares for arm 'kick', seed 0: "
        "engine differ"
    )


def test_nested_and_one_sided_keys_are_named(trained, tmp_path):
    study = copy_of(trained, tmp_path, **{
        "optimizer = {{ population = 4 }}":
        'optimizer = {{ population = 4, elite = 1 }}\nengine = "numpy"',
    })  # fmt: skip
    got = user_error(S.check_run, study, study.arms["kick"], 0)
    assert got.endswith(": engine, optimizer.elite differ"), got
    assert S._differences({"a": {"b": 1, "c": 2}, "d": 1}, {"a": {"b": 1}, "e": 1},
                          "x.") == ["x.a.c", "x.d", "x.e"]  # fmt: skip
    assert S._differences({"a": {"b": 1}}, {"a": 1}) == ["a"]
    assert S._differences({"a": 1}, {"a": 1.0}) == []


def test_a_run_longer_than_declared(trained, tmp_path):
    study = copy_of(trained, tmp_path, **{"generations = 2\n": "generations = 1\n"})
    path = study.arms["kick"].run_dir(0)
    assert user_error(S.check_run, study, study.arms["kick"], 0) == (
        f"{path}: has 2 generations, arm 'kick' declares 1"
    )
    longer = copy_of(
        trained, tmp_path / "l", **{"generations = 2\n": "generations = 3\n"}
    )
    S.check_run(longer, longer.arms["kick"], 0)  # shorter than declared: continued


def test_a_composed_run_built_on_other_runs(trained, tmp_path):
    """The kick arm names another kick run (seed 1's): the composed run was
    not built on it."""
    _, study = trained
    other = tmp_path / "other"
    train(study.arms["kick"].config(1), other, progress=False)
    moved = copy_of(trained, tmp_path, **{
        'behaviour = "kick"\nscore = false':
        f'behaviour = "kick"\nscore = false\npaths = {{{{ "0" = "{other}" }}}}'
    })  # fmt: skip
    got = user_error(S.check_run, moved, moved.arms["c"], 0)
    runs = ", ".join(str(d) for d in (other, moved.arms["getup"].run_dir(0),
                                      moved.arms["legs"].run_dir(0)))  # fmt: skip
    assert got == (
        f"{moved.arms['c'].run_dir(0)}: built on other runs than arm 'c' names for "
        f"seed 0 ({runs})"
    )


def test_the_runs_a_composed_arm_builds_on_must_have_a_best_genome(trained, tmp_path):
    study = copy_of(trained, tmp_path)
    legs = study.arms["legs"].run_dir(0)
    (legs / rundir.BEST).unlink()
    assert user_error(S.frozen_genomes, study, study.arms["c"], 0) == (
        f"arm 'c', seed 0: the return-legs run it builds on ({legs}, arm 'legs') "
        "has no best genome yet"
    )
    assert user_error(S.frozen_genomes, study, study.arms["c"], 1) == (
        "arm 'c', seed 1: the kick run it builds on "
        f"({study.arms['kick'].run_dir(1)}, arm 'kick') has no best genome yet"
    )


def test_frozen_genomes_are_the_best_of_each_run(trained):
    _, study = trained
    got = S.frozen_genomes(study, study.arms["c"], 0)
    assert [Path(p) for p in got.sources] == [
        study.arms[a].run_dir(0) for a in ("kick", "getup", "legs")
    ]
    for genome, arm in zip(got.genomes, ("kick", "getup", "legs"), strict=True):
        d = study.arms[arm].run_dir(0)
        cfg = rundir.load_config(d / rundir.CONFIG)
        assert (genome == rundir.load_best(d, cfg, len(genome)).genome).all()
    cfg = rundir.load_config(study.arms["c"].run_dir(0) / rundir.CONFIG)
    assert got.digest == cfg.frozen_digest


def _extending(trained, tmp_path: Path, source: str, generations: int = 3):
    """The study with its kick arm extending ``source`` (a template)."""
    return load_study(study_file(tmp_path, **{
        'behaviour = "kick"\nscore = false':
        f'behaviour = "kick"\nscore = false\ngenerations = {generations}\n'
        f'extends = "{source}"',
    }))  # fmt: skip


@pytest.mark.parametrize(
    "case", ["missing", "no-checkpoint", "stopped", "unfinished", "not-longer",
             "other-config", "copied"],
)  # fmt: skip
def test_a_run_to_extend(trained, tmp_path, case):
    _, study = trained
    src = tmp_path / "src"
    shutil.copytree(study.arms["kick"].run_dir(0).parent, src)
    template, generations = f"{src}/seed-{{{{seed}}}}", 3
    what = f"arm 'kick', seed 0 extends {src}/seed-0"
    if case == "missing":
        template, want = (
            "nowhere/{{seed}}",
            "arm 'kick', seed 0 extends nowhere/0: no run there",
        )
    elif case == "no-checkpoint":
        (src / "seed-0" / rundir.CHECKPOINT).unlink()
        want = (f"{what}: it holds no {rundir.CHECKPOINT} to continue from (a "
                "shipped run keeps none)")  # fmt: skip
    elif case == "stopped":
        (src / "seed-0" / rundir.STOP).write_text("{}")
        want = (f"{what}: its optimizer stopped it early ({rundir.STOP}): it "
                "cannot be continued")  # fmt: skip
    elif case == "unfinished":
        shutil.rmtree(src / "seed-0")
        train(
            study.arms["kick"].config(0), src / "seed-0", progress=False, stop_after=1
        )
        want = f"{what}: not finished (1 of 2 generations)"
    elif case == "not-longer":
        generations = 2
        want = f"{what}: it has 2 generations; the arm's 2 must be more"
    elif case == "other-config":
        shutil.rmtree(src / "seed-0")
        cfg = study.arms["kick"].config(0).replace(engine="numpy")
        train(cfg, src / "seed-0", progress=False)
        want = (f"{src}/seed-0: not the run {tmp_path / 's.toml'} declares for arm "
                "'kick', seed 0: engine differ")  # fmt: skip
    else:  # copied already: the copy is checked, not what it was copied from
        longer = _extending(trained, tmp_path, template)
        shutil.copytree(src / "seed-0", longer.arms["kick"].run_dir(0))
        (src / "seed-0" / rundir.CHECKPOINT).unlink()
        S.check_run(longer, longer.arms["kick"], 0)
        return
    longer = _extending(trained, tmp_path, template, generations)
    assert user_error(S.check_run, longer, longer.arms["kick"], 0) == want


def test_a_repertoire_arm_is_given_its_elites(tmp_path):
    """``composed-repertoire`` with 2 elites: 4 frozen genomes, not 8 + 2."""
    text = TEXT.replace('behaviour = "composed"', 'behaviour = "composed-repertoire"\n'
                        "options = {{ elites = 2 }}")  # fmt: skip
    qd = 'optimizer = {{ kind = "map-elites", population = 4 }}'
    text = text.replace('behaviour = "kick"\nscore = false',
                        f'behaviour = "kick"\nscore = false\n{qd}')  # fmt: skip
    study = load_study(study_file(tmp_path, text))
    beh = S.behaviour_for(study.arms["c"].config(0))
    assert beh.frozen.shape == (4, beh.frozen_num_params())
    debris = '{{ kind = "debris", seed = 7, terrains = 2 }}'
    on = load_study(study_file(tmp_path, text.replace(
        "[arms.kick]", f"scene = {debris}\n[arms.kick]", 1)))  # fmt: skip
    beh = S.behaviour_for(on.arms["c"].config(0))
    assert beh.terrains == on.arms["c"].config(0).scene and beh.terrains.count == 2
    pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")
    for arm in ("kick", "getup", "legs"):
        train_run(study, arm, 0)
    got = S.frozen_genomes(study, study.arms["c"], 0)
    assert got.genomes.shape[0] == 4 and got.behaviours[:3] == ("kick", "kick", "getup")


def test_the_behaviour_given_is_the_one_counted(trained):
    _, study = trained
    cfg = study.arms["kick"].config(0)
    twice = dataclasses.replace(cfg.options, score_substeps=(6, 12))
    beh = S.behaviour_for(cfg.replace(options=twice))
    assert S.episode_steps(cfg, beh) == 3 * S.episode_steps(cfg)


def test_a_copy_to_be_made_counts_what_it_will_bring(trained, tmp_path):
    _, study = trained
    src = tmp_path / "src"
    shutil.copytree(study.arms["kick"].run_dir(0).parent, src)
    longer = _extending(trained, tmp_path, f"{src}/seed-{{{{seed}}}}")
    got = {(s.arm, s.seed): s for s in S.states(longer)}
    assert (got[("kick", 0)].done, got[("kick", 0)].generations) == (2, 3)
    assert got[("kick", 1)].done == 0  # nothing there to copy
    path = longer.arms["kick"].run_dir(0)
    train(longer.arms["kick"].config(0), path, progress=False, stop_after=1)
    assert {(s.arm, s.seed): s for s in S.states(longer)}[("kick", 0)].done == 1


def test_metrics_without_a_run_are_no_generations(trained, tmp_path):
    _, study = trained
    (tmp_path / rundir.METRICS).write_bytes(
        (study.arms["kick"].run_dir(0) / rundir.METRICS).read_bytes()
    )
    assert S.generations_done(tmp_path) == 0


def test_a_frozen_run_of_another_network_size(trained, tmp_path, monkeypatch):
    import locustjump.tasks as T
    from locustjump.rundir.config import TrainConfig
    from locustjump.sim.controller import MLP
    from locustjump.tasks.kick import Kick

    class WideKick(Kick):
        name = "kick-wide"

        @property
        def controller(self):
            return MLP(n_hidden=12)

    monkeypatch.setitem(T._REGISTRY, "kick-wide", WideKick)
    wide = tmp_path / "wide"
    cfg = trained[1].arms["kick"].config(0)
    train(TrainConfig.from_dict({**cfg.to_dict(), "behaviour": "kick-wide"}, "t"),
          wide, progress=False)  # fmt: skip
    moved = copy_of(trained, tmp_path, **{
        'behaviour = "kick"\nscore = false':
        f'behaviour = "kick"\nscore = false\npaths = {{{{ "0" = "{wide}" }}}}'
    })  # fmt: skip
    assert user_error(S.frozen_genomes, moved, moved.arms["c"], 0) == (
        f"frozen_kick {wide}: holds a 'kick-wide' run, not 'kick' "
        f"({MLP(n_hidden=12).num_params} genes, not {MLP().num_params})"
    )
