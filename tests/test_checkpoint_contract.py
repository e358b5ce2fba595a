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
from locustjump.evo.map_elites import MapElitesParams
from locustjump.evo.rcga import RCGA
from locustjump.rundir.checkpoint import (
    check_kept_best,
    checkpoint_bytes,
    read_checkpoint,
    write_checkpoint,
)
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


# --- how large a checkpoint may be ------------------------------------------------


def test_the_size_bound_counts_what_a_checkpoint_holds():
    # RCGA, population n = 4, g = 9 generations, p = 5 genes: a population and
    # its fitness n (p + 1), the best genome and the mean's p each 2 p, the
    # fitness of every genome told g n; 8 bytes each, beside 64 KiB of text
    assert checkpoint_bytes(CFG, P) == (1 << 16) + 8 * (4 * 6 + 2 * 5 + 9 * 4)
    # a QD optimizer: every genome told with its d = 2 descriptors, and an
    # archive of 3 x 4 cells, each a genome, its descriptors, fitness, index
    # and generation
    qd = CFG.replace(optimizer=MapElitesParams(population=4, cells=(3, 4)))
    assert len(qd.optimizer.descriptors) == 2
    told, archive = 9 * 4 * (1 + 2), 12 * (5 + 2 + 3)
    assert checkpoint_bytes(qd, P) == (1 << 16) + 8 * (4 * 6 + 2 * 5 + told + archive)


def padded(extra):
    """arrays() with an ``opt_pad`` array that brings their declared bytes to
    exactly the checkpoint bound, plus ``extra`` bytes."""
    z = arrays()
    used = sum(np.asarray(v).nbytes for v in z.values())
    return {**z, "opt_pad": np.zeros(checkpoint_bytes(CFG, P) - used + extra, np.uint8)}


def test_a_checkpoint_at_its_bound_is_read_and_one_byte_more_is_not(tmp_path):
    path = tmp_path / "checkpoint.npz"
    save_npz(path, **padded(0))
    assert "pad" in read_checkpoint(path, CFG, P)[2]
    save_npz(path, **padded(1))
    bound = checkpoint_bytes(CFG, P)
    message = (
        f"{path}: its arrays declare {bound + 1:,} bytes, more than such a file "
        f"holds ({bound:,}; nothing inflated)"
    )
    with pytest.raises(UserError, match=exactly(message)):
        read_checkpoint(path, CFG, P)


# --- an optimizer's own state keys --------------------------------------------------


def test_given_its_state_keys_only_those_are_read(tmp_path):
    _, state = optimizer_state()
    keys = tuple(state)
    path = tmp_path / "checkpoint.npz"
    save_npz(path, **arrays())
    assert sorted(read_checkpoint(path, CFG, P, keys)[2]) == sorted(keys)
    save_npz(path, **arrays(opt_junk=np.zeros(2)))
    assert "junk" in read_checkpoint(path, CFG, P)[2]  # any prefixed key
    message = f"{path}: holds 'opt_junk.npy', which such a file does not (nothing read)"
    with pytest.raises(UserError, match=exactly(message)):
        read_checkpoint(path, CFG, P, keys)


def test_a_missing_state_key_is_named(tmp_path):
    _, state = optimizer_state()
    path = tmp_path / "checkpoint.npz"
    gone = sorted(k for k in state if k != "generation")[:2]
    save_npz(path, **arrays(**{"opt_" + k: None for k in gone}))
    message = f"{path}: missing {', '.join('opt_' + k for k in gone)}"
    with pytest.raises(UserError, match=exactly(message)):
        read_checkpoint(path, CFG, P, tuple(state))
    # a checkpoint from before pluggable optimizers holds the RCGA's keys,
    # unprefixed: an optimizer's keys are not asked of it
    z = arrays(optimizer=None, **{"opt_" + k: None for k in state})
    save_npz(path, **z, **state)
    got = read_checkpoint(path, CFG, P, (*state, "later"))[2]
    assert sorted(got) == sorted(state)


# --- best.npz, which a resumed run keeps ---------------------------------------------


def held_best(generation=2, fitness=-1.0, genome=None):
    genome = np.arange(P, dtype=float) if genome is None else genome
    return BestGenome(genome, fitness, generation, "kick", CFG.hash())


def test_no_best_is_right_only_before_the_first_checkpoint(tmp_path):
    assert check_kept_best(tmp_path, CFG, P, None, 0) is None
    message = (
        f"{tmp_path / 'best.npz'}: missing, but checkpoint.npz holds 2 generations"
    )
    with pytest.raises(UserError, match=exactly(message)):
        check_kept_best(tmp_path, CFG, P, held_best(), 2)


@pytest.mark.parametrize(
    "kept, held, done",
    [
        (held_best(), held_best(), 2),  # the checkpoint's own best
        (held_best(3, -0.5), held_best(), 2),  # a better one of the next generation
        (held_best(1, -3.0), None, 0),  # the first, saved before a checkpoint
    ],
)
def test_the_checkpoint_s_best_or_a_better_next_one_is_kept(tmp_path, kept, held, done):
    kept.save(tmp_path / "best.npz")
    assert check_kept_best(tmp_path, CFG, P, held, done) is None


@pytest.mark.parametrize(
    "kept, held, done, had",
    [
        (held_best(genome=np.ones(P)), held_best(), 2, "generation 2's"),
        (held_best(fitness=-0.5), held_best(), 2, "generation 2's"),
        (held_best(1), held_best(), 2, "generation 2's"),
        (held_best(3, -1.0), held_best(), 2, "generation 2's"),  # not better
        (held_best(3, -2.0), held_best(), 2, "generation 2's"),
        (held_best(4, -0.5), held_best(), 2, "generation 2's"),  # a generation on
        (held_best(1, -0.5), held_best(), 2, "generation 2's"),  # an earlier one
        (held_best(2, -3.0), None, 0, "none"),
    ],
)
def test_any_other_best_is_refused_and_kept(tmp_path, kept, held, done, had):
    path = tmp_path / "best.npz"
    kept.save(path)
    before = path.read_bytes()
    message = (
        f"{path}: generation {kept.generation}'s best (fitness {kept.fitness:.6g}) "
        f"is not the best genome checkpoint.npz holds ({had}; nothing changed)"
    )
    with pytest.raises(UserError, match=exactly(message)):
        check_kept_best(tmp_path, CFG, P, held, done)
    assert path.read_bytes() == before


def test_a_kept_best_is_checked_as_evaluate_checks_it(tmp_path):
    path = tmp_path / "best.npz"
    BestGenome(np.zeros(P), -1.0, 2, "kick", "0123456789abcdef").save(path)
    message = (
        f"{path}: belongs to another run (kick, hash 0123456789abcdef; "
        f"config.toml: kick, hash {CFG.hash()})"
    )
    with pytest.raises(UserError, match=exactly(message)):
        check_kept_best(tmp_path, CFG, P, held_best(), 2)
    held_best(genome=np.zeros(P + 1)).save(path)
    with pytest.raises(UserError, match=re.escape(f"{path}: genome has 6 genes")):
        check_kept_best(tmp_path, CFG, P, held_best(), 2)
