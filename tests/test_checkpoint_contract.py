"""checkpoint.npz (rundir/checkpoint.py): what is written reads back as it
was, an older RCGA checkpoint reads as the RCGA's, and each way a checkpoint
can disagree with its run is one line naming the file and what is wrong.

Written against the mutants the suite let through (issue #48,
scripts/mutation.py).
"""

import re

import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.evo import RCGAParams
from locustjump.evo.cma import CMAParams
from locustjump.evo.rcga import RCGA
from locustjump.rundir.checkpoint import read_checkpoint, write_checkpoint
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.files import save_npz
from locustjump.rundir.run import BestGenome

P = 5
CFG = TrainConfig(optimizer=RCGAParams(population=4, elite=1), generations=9)


def exactly(message):
    return "^" + re.escape(message) + "$"


def optimizer_state(generations=2):
    ga = RCGA(P, CFG.optimizer, 3)
    for _ in range(generations):
        x = ga.ask()
        ga.tell(-np.sum(x**2, axis=1))
    return ga, ga.state()


def best_of(ga, generation):
    return BestGenome(ga.best, ga.best_fitness, generation, "kick", CFG.hash())


def arrays(**changes):
    """What write_checkpoint writes for a run at generation 2, with changes
    (None: leave that key out)."""
    ga, state = optimizer_state()
    z = {
        "format": np.array(1),
        "behaviour": np.array("kick"),
        "config_hash": np.array(CFG.hash()),
        "optimizer": np.array("rcga"),
        "best_genome": ga.best,
        "best_fitness": np.array(ga.best_fitness),
        "best_generation": np.array(2),
        "metrics_row": np.array("2,1,1,1,1,1,1,1\n"),
        **{"opt_" + k: v for k, v in state.items()},
    }
    z.update(changes)
    return {k: v for k, v in z.items() if v is not None}


def test_what_is_written_reads_back(tmp_path):
    ga, state = optimizer_state()
    path = tmp_path / "checkpoint.npz"
    write_checkpoint(path, CFG, best_of(ga, 1), "2,0.5,0,0,1,8,80,9\n", state)
    best, row, got = read_checkpoint(path, CFG, P)
    assert row == "2,0.5,0,0,1,8,80,9\n"
    np.testing.assert_array_equal(best.genome, ga.best)
    assert (best.fitness, best.generation, best.behaviour, best.config_hash) == (
        ga.best_fitness,
        1,
        "kick",
        CFG.hash(),
    )
    assert sorted(got) == sorted(state)
    for k in state:
        np.testing.assert_array_equal(got[k], state[k])
    with np.load(path) as z:
        assert str(z["optimizer"]) == "rcga" and int(z["format"]) == 1


def test_a_checkpoint_from_before_pluggable_optimizers_is_the_rcga_s(tmp_path):
    _, state = optimizer_state()
    z = arrays(optimizer=None, **{"opt_" + k: None for k in state})
    z.update(state)  # the RCGA's keys at the top level, unprefixed
    save_npz(tmp_path / "c.npz", **z)
    _, _, got = read_checkpoint(tmp_path / "c.npz", CFG, P)
    assert sorted(got) == sorted(state)
    save_npz(tmp_path / "d.npz", **{k: v for k, v in z.items() if k != "fitness"})
    with pytest.raises(
        UserError, match=exactly(f"{tmp_path / 'd.npz'}: missing fitness")
    ):
        read_checkpoint(tmp_path / "d.npz", CFG, P)


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"behaviour": np.array("getup")}, "holds a 'getup' run, not 'kick'"),
        (
            {"optimizer": np.array("cma")},
            "was written by the 'cma' optimizer, the run's config.toml names 'rcga'",
        ),
        (
            {"config_hash": np.array("0123456789abcdef")},
            f"was written by another configuration (hash 0123456789abcdef, "
            f"config.toml has {CFG.hash()})",
        ),
        ({"opt_generation": None}, "missing opt_generation"),
        (
            {"opt_fitness": np.array([1, 2j, 3, 4])},
            "fitness holds complex128 values, not numbers",
        ),
        ({"opt_fitness": np.array([1.0, np.nan, 3, 4])}, "fitness holds NaN"),
        (
            {"best_generation": np.array(0)},
            "best_generation 0 is not one of the 2 generations it has done",
        ),
        (
            {"best_generation": np.array(3)},
            "best_generation 3 is not one of the 2 generations it has done",
        ),
        ({"best_genome": np.zeros(P + 1)}, "best_genome has shape (6,), expected (5,)"),
        (
            {"metrics_row": np.array("2,1,1,1,1,1,1,1")},
            "metrics_row is not the row of generation 2: '2,1,1,1,1,1,1,1'",
        ),
        (
            {"metrics_row": np.array("1,1,1,1,1,1,1,1\n")},
            "metrics_row is not the row of generation 2: '1,1,1,1,1,1,1,1'",
        ),
        (
            {"metrics_row": np.array("12,1,1,1,1,1,1,1\n")},
            "metrics_row is not the row of generation 2: '12,1,1,1,1,1,1,1'",
        ),
        (
            {"behaviour": np.array(1)},
            "behaviour must be text, got a int64 array of shape ()",
        ),
        (
            {"config_hash": np.array([CFG.hash()])},
            "config_hash must be text, got a <U16 array of shape (1,)",
        ),
        (
            {"opt_generation": np.array(2.0)},
            "generation must be an integer, got a float64 array of shape ()",
        ),
        (
            {"best_fitness": np.array("1")},
            "best_fitness must be a float64 number, got a <U1 array of shape ()",
        ),
        (
            {"best_generation": np.array(1.0)},
            "best_generation must be an integer, got a float64 array of shape ()",
        ),
        (
            {"metrics_row": np.array(2)},
            "metrics_row must be text, got a int64 array of shape ()",
        ),
        (
            {"metrics_row": np.array("2," + "9" * 100)},
            f"metrics_row is not the row of generation 2: {('2,' + '9' * 100)[:60]!r}",
        ),
    ],
)
def test_each_disagreement_with_the_run_is_one_line(tmp_path, changes, message):
    path = tmp_path / "checkpoint.npz"
    save_npz(path, **arrays(**changes))
    with pytest.raises(UserError, match=exactly(f"{path}: {message}")):
        read_checkpoint(path, CFG, P)


def test_the_best_may_be_of_the_last_generation(tmp_path):
    path = tmp_path / "checkpoint.npz"
    save_npz(path, **arrays(best_generation=np.array(2)))
    assert read_checkpoint(path, CFG, P)[0].generation == 2


def test_another_optimizer_s_run_is_named_by_its_config(tmp_path):
    cfg = CFG.replace(optimizer=CMAParams(population=4))
    path = tmp_path / "checkpoint.npz"
    save_npz(path, **arrays())
    with pytest.raises(
        UserError,
        match=exactly(
            f"{path}: was written by the 'rcga' optimizer, the run's config.toml "
            "names 'cma'"
        ),
    ):
        read_checkpoint(path, cfg, P)
