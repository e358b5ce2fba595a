"""Quality diversity: the MAP-Elites and CMA-ME optimizers (pyribs), the
archive's arrays and the task's behaviour descriptors."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

from locustjump import rundir
from locustjump.evo import (
    CMAME,
    Archive,
    CMAMEParams,
    MapElites,
    MapElitesParams,
    RCGAParams,
    make_optimizer,
)
from locustjump.rundir.config import TrainConfig
from locustjump.sim import model as lm
from locustjump.sim.engine.job import RolloutResult
from locustjump.tasks import Kick
from locustjump.tasks.kick import kick_descriptors
from locustjump.tasks.reference import run_rules

pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")

GRID = {"descriptors": ("a", "b"), "ranges": ((0.0, 1.0), (0.0, 1.0))}
KINDS = {
    "map-elites": MapElitesParams(population=8, cells=(5, 5), **GRID),
    "iso-line": MapElitesParams(
        population=8, cells=(5, 5), variation="iso-line", sigma=0.05, **GRID
    ),
    "cma-me": CMAMEParams(population=8, emitters=2, cells=(5, 5), **GRID),
}


def _problem(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fitness (maximised at 0.3) and two descriptors in [0, 1] of genomes x."""
    return -np.sum((x - 0.3) ** 2, axis=1), np.clip(np.abs(x[:, :2]), 0, 1)


def _run(opt, generations: int) -> list[np.ndarray]:
    asked = []
    for _ in range(generations):
        x = opt.ask()
        asked.append(x)
        opt.tell(*_problem(x))
    return asked


# --- the optimizers -----------------------------------------------------------


@pytest.mark.parametrize("kind", list(KINDS))
def test_resumed_from_its_arrays_it_goes_on_bit_for_bit(kind, tmp_path):
    """N generations in one go equal N/2, a state written to an .npz and read
    back without pickle into a fresh optimizer, then N/2 more."""
    params = KINDS[kind]
    whole = make_optimizer(params, 5, seed=4)
    asked = _run(whole, 12)
    half = make_optimizer(params, 5, seed=4)
    _run(half, 6)
    np.savez(tmp_path / "state.npz", **half.state())
    with np.load(tmp_path / "state.npz", allow_pickle=False) as z:
        state = {k: z[k] for k in z.files}
    resumed = make_optimizer(params, 5, seed=4)
    resumed.load_state(state)
    for a, b in zip(asked[6:], _run(resumed, 6), strict=True):
        np.testing.assert_array_equal(a, b)
    for k in ("index", "solution", "objective", "measures", "generation"):
        np.testing.assert_array_equal(
            getattr(whole.archive(), k), getattr(resumed.archive(), k)
        )
    assert whole.diagnostics() == resumed.diagnostics()
    assert whole.best_fitness == resumed.best_fitness
    # another seed, other genomes
    assert not np.array_equal(make_optimizer(params, 5, 5).ask(), asked[0])


def test_a_state_whose_archive_the_replay_does_not_give_is_refused():
    opt = make_optimizer(KINDS["map-elites"], 5, seed=1)
    _run(opt, 3)
    state = opt.state()
    state["archive_objective"] = state["archive_objective"] + 1e-12
    with pytest.raises(ValueError, match="archive_objective is not what replaying"):
        make_optimizer(KINDS["map-elites"], 5, seed=1).load_state(state)


@pytest.mark.parametrize("kind", ["map-elites", "cma-me"])
def test_the_archive_holds_each_cells_best_as_plain_map_elites_would(kind):
    """pyribs' archive against a plain reference: the best genome told so
    far in each cell of the grid (cells by floor((v - low) / width), the
    edges clipped), with the generation that found it."""
    opt = make_optimizer(KINDS[kind], 5, seed=2)
    best: dict[int, tuple[float, int, np.ndarray]] = {}
    for g in range(1, 16):
        x = opt.ask()
        f, d = _problem(x)
        opt.tell(f, d)
        cells = np.minimum((d * 5 + 1e-6).astype(int), 4)
        for xi, fi, (i, j) in zip(x, f, cells, strict=True):
            c = i * 5 + j
            if c not in best or fi > best[c][0]:
                best[c] = (fi, g, xi)
    a = opt.archive()
    assert sorted(best) == sorted(a.index.tolist())
    for pos, c in enumerate(a.index):
        fi, g, xi = best[int(c)]
        assert a.objective[pos] == fi and a.generation[pos] == g
        np.testing.assert_array_equal(a.solution[pos], xi)
    s = opt.diagnostics()
    assert s["coverage"] == len(best) / 25 == a.coverage
    assert s["archive_best"] == max(v[0] for v in best.values()) == opt.best_fitness
    assert math.isclose(s["qd_score"], sum(v[0] for v in best.values()))


def test_the_first_genomes_are_the_rcgas_uniform_start_and_every_emitter_asks():
    p = MapElitesParams(population=7, emitters=3, **GRID, cells=(2, 2))
    opt = MapElites(4, p, seed=0)
    x = opt.ask()
    assert p.batch_sizes() == [3, 2, 2] and x.shape == (7, 4)
    assert np.abs(x).max() <= p.init_scale
    np.testing.assert_array_equal(x, np.random.default_rng(0).uniform(-1, 1, (7, 4)))


def test_descriptors_go_with_the_tell_and_only_to_an_optimizer_that_needs_them():
    qd = make_optimizer(KINDS["map-elites"], 5, 0)
    x = qd.ask()
    with pytest.raises(ValueError, match="needs the descriptors a, b"):
        qd.tell(_problem(x)[0])
    with pytest.raises(ValueError, match="shape"):
        qd.tell(_problem(x)[0], np.zeros((len(x), 3)))
    with pytest.raises(ValueError, match="not finite"):
        qd.tell(_problem(x)[0], np.full((len(x), 2), np.nan))
    ga = make_optimizer(RCGAParams(population=4), 5, 0)
    assert ga.descriptor_names == ()
    n = len(ga.ask())
    with pytest.raises(ValueError, match="takes no descriptors"):
        ga.tell(np.zeros(n), np.zeros((n, 2)))
    ga.tell(np.zeros(n))  # unchanged for the others


def test_a_qd_optimizer_needs_its_grid_and_cma_me_two_genomes_an_emitter():
    with pytest.raises(ValueError, match="needs its descriptors"):
        CMAME(5, CMAMEParams(), 0)
    message = "^population must be >= 2 per emitter \\(5 emitters: >= 10\\), got 9$"
    with pytest.raises(ValueError, match=message):
        CMAMEParams(population=9, emitters=5)
    with pytest.raises(ValueError, match="at most 10,000"):
        MapElitesParams(cells=(200, 200))
    with pytest.raises(ValueError, match="variation"):
        MapElitesParams(variation="line")


# --- the archive's arrays -----------------------------------------------------


def _archive() -> Archive:
    return Archive(
        ("x", "y"), np.array([0.0, -1.0]), np.array([1.0, 1.0]), (2, 3),
        np.array([5, 0, 3]), np.arange(6.0).reshape(3, 2),
        np.array([0.5, 2.0, 0.5]), np.array([[0.9, 0.9], [0.1, -0.9], [0.6, -0.9]]),
        np.array([1, 1, 2]),
    )  # fmt: skip


def test_an_archive_ranks_its_elites_and_finds_a_cell():
    a = _archive()
    assert a.ranked().tolist() == [1, 2, 0]  # ties: the lower cell first
    assert a.at_rank(0) == 1 and a.at_cell((1, 2)) == 0 and a.at_cell((1, 0)) == 2
    assert a.grid_index().tolist() == [[1, 2], [0, 0], [1, 0]]
    heat = a.heat()
    assert heat[1, 2] == 0.5 and np.isnan(heat[0, 1]) and a.coverage == 0.5
    assert a.qd_score() == 3.0 and a.qd_score(offset=1.0) == 0.0
    for bad, needle in (((0, 1), "empty"), ((2, 0), "outside"), ((1,), "2 desc")):
        with pytest.raises(IndexError, match=needle):
            a.at_cell(bad)
    with pytest.raises(IndexError, match="holds 3"):
        a.at_rank(3)
    assert a.in_cell_order().index.tolist() == [0, 3, 5]


def test_the_heatmap_title_gives_the_qd_score_less_the_runs_offset():
    from matplotlib.figure import Figure

    from locustjump.present.plots import draw_archive

    for offset, score in ((0.0, "3"), (1.0, "0"), (-2.0, "9")):
        fig = Figure()
        ax = fig.add_subplot()
        draw_archive(fig, ax, _archive(), qd_offset=offset)
        assert f"coverage 50%, QD score {score}" in ax.get_title()


# --- the kick's behaviour descriptors -----------------------------------------


def test_kick_descriptors_of_a_hand_made_jump_and_of_an_unstable_episode(params):
    L = params.body_length
    t = np.linspace(0, 1, 11)
    qpos = np.zeros((2, 11, 11))
    qpos[:, :, 0] = 2.0 * L * t  # steadily ahead: 2 body lengths by the end
    qpos[:, :, 2] = 0.1 + 4 * L * t * (1 - t)  # rise of 1 L at t = 0.5
    d = kick_descriptors(qpos, L)
    assert d["apex_rise"][0] == pytest.approx(1.0)
    assert d["apex_distance"][0] == pytest.approx(1.0)
    assert d["apex_angle"][0] == pytest.approx(45.0)
    res = RolloutResult({"qpos": qpos}, np.array([False, True]), np.array([10, 3]))
    got = Kick().describe(res, params, ("apex_angle", "apex_rise"))
    np.testing.assert_allclose(got, [[45.0, 1.0], [0.0, 0.0]])  # unstable: low


def test_descriptors_of_the_rule_based_kick(params):
    """The paper's rule-based kick from the ready posture: its apex in the
    first 300 steps is 3.18 body lengths up and 0.57 ahead, at 79.8 deg."""
    rules = run_rules(steps=Kick.n_steps, model_params=params)
    res = RolloutResult(
        {"qpos": rules.qpos[None]}, np.array([False]), np.array([Kick.n_steps])
    )
    names = ("apex_rise", "apex_distance", "apex_angle")
    got = Kick().describe(res, params, names)[0]
    q = rules.qpos
    top = int(np.argmax(q[:, 2]))  # the plain reading of the docstring
    rise, ahead = q[top, 2] - q[0, 2], q[top, 0] - q[0, 0]
    L = params.body_length
    np.testing.assert_allclose(
        got, [rise / L, ahead / L, math.degrees(math.atan2(rise, ahead))]
    )
    np.testing.assert_allclose(got, [3.182, 0.5728, 79.79], rtol=2e-3)


def test_the_config_resolves_the_tasks_descriptors_and_refuses_others(tmp_path):
    cfg = TrainConfig(optimizer=MapElitesParams())
    assert cfg.optimizer.descriptors == ("apex_distance", "apex_rise")
    assert cfg.optimizer.ranges == ((-5.0, 15.0), (0.0, 5.0))
    assert cfg.optimizer.cells == (10, 10)
    rundir.write_config(tmp_path / "c.toml", cfg)
    assert rundir.load_config(tmp_path / "c.toml") == cfg
    angle = TrainConfig(optimizer=CMAMEParams(descriptors=("apex_angle",)))
    assert angle.optimizer.ranges == ((0.0, 180.0),)
    with pytest.raises(ValueError, match="unknown descriptor 'height'; kick declares"):
        TrainConfig(optimizer=MapElitesParams(descriptors=("height",)))
    with pytest.raises(ValueError, match="getup declares none"):
        TrainConfig(behaviour="getup", optimizer=MapElitesParams())


def test_the_rule_based_kick_descriptors_use_the_models_scale():
    """Descriptors are in body lengths: doubling the creature's scale leaves
    a trajectory scaled with it where it was."""
    small, big = lm.LocustParams(), lm.LocustParams(scale=20.0)
    qpos = np.zeros((1, 3, 11))
    qpos[0, 1, :3] = (small.body_length, 0, 2 * small.body_length)
    a = kick_descriptors(qpos, small.body_length)
    b = kick_descriptors(qpos * big.body_length / small.body_length, big.body_length)
    for k in a:
        np.testing.assert_allclose(a[k], b[k])


_THREADS = """
import hashlib, numpy as np
from locustjump.evo import make_optimizer, CMAMEParams
p = CMAMEParams(population=50, descriptors=("a", "b"), ranges=((0, 1), (0, 1)),
                cells=(10, 10))
o = make_optimizer(p, 144, 0)
for g in range(40):
    x = o.ask()
    o.tell(-np.sum((x - 0.3) ** 2, 1), np.clip(np.abs(x[:, :2]), 0, 1))
a = o.archive()
print(hashlib.sha256(a.solution.tobytes() + o.ask().tobytes()).hexdigest())
"""


@pytest.mark.slow
def test_cma_me_gives_the_same_genomes_on_any_number_of_blas_threads():
    """CMA-ME's eigendecompositions and products run on BLAS, which may
    split them among threads: 144 genes, 40 generations, 1 and 4 threads."""
    out = []
    for n in ("1", "4"):
        env = {**os.environ, "OPENBLAS_NUM_THREADS": n, "OMP_NUM_THREADS": n,
               "MKL_NUM_THREADS": n}  # fmt: skip
        r = subprocess.run([sys.executable, "-c", _THREADS], env=env,
                           capture_output=True, text=True, check=True)  # fmt: skip
        out.append(r.stdout.strip())
    assert out[0] == out[1]
