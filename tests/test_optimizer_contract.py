"""The optimizer base class (evo/base.py) and random search
(evo/random_search.py) stated exactly: each error's one line, what a stop
reason's value becomes, which genome is the best, the generator's state
round trip, and random search's sample, state and ranges.

Written against the mutants the rest of the suite let through (issue #48,
scripts/mutation.py).
"""

import json
import re

import numpy as np
import pytest

from helpers import Fixed, exactly
from locustjump.evo import (
    RCGA,
    RandomSearch,
    RandomSearchParams,
    RCGAParams,
)
from locustjump.evo.base import check_fitness, rng_from_state, rng_state

# --- evo/base.py ---------------------------------------------------------------


def test_check_fitness_flattens_to_float64_and_names_what_is_wrong():
    f = check_fitness([[1], [2]], 2)
    assert f.dtype == np.float64 and f.shape == (2,)
    np.testing.assert_array_equal(f, [1.0, 2.0])
    with pytest.raises(ValueError, match=exactly("got 3 fitness values for 4 genomes")):
        check_fitness(np.zeros(3), 4)
    with pytest.raises(ValueError, match=exactly("fitness contains NaN")):
        check_fitness([0.0, np.nan], 2)
    np.testing.assert_array_equal(
        check_fitness([-np.inf, np.inf], 2), [-np.inf, np.inf]
    )


def test_a_generator_state_round_trips_and_an_unknown_one_is_named():
    rng = np.random.default_rng(5)
    rng.random(3)
    text = rng_state(rng)
    assert text.shape == () and json.loads(str(text))["bit_generator"] == "PCG64"
    again = rng_from_state(text)
    np.testing.assert_array_equal(again.random(4), rng.random(4))
    dxsm = np.random.Generator(np.random.PCG64DXSM(3))
    again = rng_from_state(rng_state(dxsm))
    np.testing.assert_array_equal(again.random(2), dxsm.random(2))
    bad = json.dumps({"bit_generator": "Mersenne"})
    with pytest.raises(ValueError, match=exactly("unknown bit generator 'Mersenne'")):
        rng_from_state(bad)
    with pytest.raises(ValueError, match=exactly("unknown bit generator 'Generator'")):
        rng_from_state(json.dumps({"bit_generator": "Generator"}))


@pytest.mark.parametrize(
    "value, expected",
    [
        (np.bool_(True), True),
        (False, False),
        (np.int64(7), 7),
        (3, 3),
        (np.float64(1e14), 1e14),
        (2.5, 2.5),
        (float("inf"), "inf"),
        (float("nan"), "nan"),
        ("x", "x"),
    ],
)
def test_a_stop_reason_s_value_is_a_plain_json_scalar(value, expected):
    class Stops(RandomSearch):
        def _stop(self):
            return {np.str_("why"): value}

    got = Stops(2, RandomSearchParams(population=2), 0).stop()
    assert list(got) == ["why"] and type(next(iter(got))) is str
    assert type(got["why"]) is type(expected) and got["why"] == expected


def test_the_base_checks_its_arguments_in_one_line():
    with pytest.raises(
        TypeError, match=exactly("seed must be an integer in [0, 2**63-1], got 1.5")
    ):
        RandomSearch(3, RandomSearchParams(population=2), 1.5)
    with pytest.raises(
        ValueError, match=exactly("num_params must be an integer >= 1, got 0")
    ):
        RandomSearch(0, RandomSearchParams(population=2), 0)
    opt = RandomSearch(1, RandomSearchParams(population=2), np.int64(4))
    assert opt.seed == 4 and type(opt.seed) is int and opt.num_params == 1


def test_tell_and_state_say_when_they_are_called_out_of_turn():
    opt = RandomSearch(3, RandomSearchParams(population=2), 0)
    message = (
        "tell() without a pending ask() (generation 0 is told; each ask() is told once)"
    )
    with pytest.raises(RuntimeError, match=exactly(message)):
        opt.tell(np.zeros(2))
    opt.ask()
    with pytest.raises(
        RuntimeError, match=exactly("checkpoint between generations (after tell())")
    ):
        opt.state()


def test_an_ask_of_the_wrong_shape_is_named():
    class Flat(RandomSearch):
        def _ask(self):
            return np.zeros(3)

    class Empty(RandomSearch):
        def _ask(self):
            return np.zeros((0, 3))

    with pytest.raises(
        ValueError, match=exactly("Flat._ask() gave shape (3,), expected (n, 3)")
    ):
        Flat(3, RandomSearchParams(population=2), 0).ask()
    with pytest.raises(ValueError, match=re.escape("Empty._ask() gave shape (0, 3)")):
        Empty(3, RandomSearchParams(population=2), 0).ask()


def test_the_best_is_the_first_of_the_best_told_and_kept_until_beaten():
    opt = RandomSearch(2, RandomSearchParams(population=3), 0)
    assert opt.best_fitness == -np.inf
    np.testing.assert_array_equal(opt.best, np.zeros(2))
    x = opt.ask()
    opt.tell([-5.0, -5.0, -7.0])  # a tie: the first
    np.testing.assert_array_equal(opt.best, x[0])
    assert opt.best_fitness == -5.0
    opt.ask()
    opt.tell([-5.0, -6.0, -9.0])  # equal is not better
    np.testing.assert_array_equal(opt.best, x[0])
    y = opt.ask()
    opt.tell([-9.0, -1.0, -2.0])
    np.testing.assert_array_equal(opt.best, y[1])
    assert opt.best_fitness == -1.0 and opt.generation == 3
    got = opt.best
    got[:] = 99.0  # a copy
    np.testing.assert_array_equal(opt.best, y[1])


def test_a_first_generation_of_minus_infinity_still_has_a_best():
    opt = RandomSearch(2, RandomSearchParams(population=2), 0)
    x = opt.ask()
    opt.tell([-np.inf, -np.inf])
    np.testing.assert_array_equal(opt.best, x[0])


def test_a_restored_best_is_checked():
    opt = RCGA(3, RCGAParams(population=4, elite=1), 0)
    with pytest.raises(ValueError, match=exactly("best genome has shape (2,)")):
        opt._set_best(np.zeros(2), 1.0)
    with pytest.raises(
        ValueError, match=exactly("best genome or its fitness is not finite")
    ):
        opt._set_best(np.array([0.0, np.inf, 0.0]), 1.0)
    with pytest.raises(
        ValueError, match=exactly("best genome or its fitness is not finite")
    ):
        opt._set_best(np.zeros(3), np.nan)
    opt._set_best(np.array([1, 2, 3]), -np.inf)  # -inf: nothing better yet
    assert opt.best.dtype == np.float64 and opt.best_fitness == -np.inf


def test_load_state_forgets_a_pending_ask_and_takes_the_generation():
    a = RandomSearch(3, RandomSearchParams(population=2), 0)
    a.ask()
    a.tell(np.array([1.0, 2.0]))
    state = a.state()
    assert int(state["generation"]) == 1
    b = RandomSearch(3, RandomSearchParams(population=2), 9)
    b.ask()
    b.load_state(state)
    np.testing.assert_array_equal(b.ask(), a.ask())
    assert b.generation == 1 and b.best_fitness == 2.0
    c = RandomSearch.from_state(3, RandomSearchParams(population=2), state, seed=9)
    assert c.seed == 9 and c.generation == 1


# --- evo/random_search.py ----------------------------------------------------------


def test_random_search_samples_uniformly_in_init_scale_every_generation():
    opt = RandomSearch(4, RandomSearchParams(population=500, init_scale=0.2), 1)
    x = opt.ask()
    rng = np.random.default_rng(1)
    np.testing.assert_array_equal(x, rng.uniform(-0.2, 0.2, size=(500, 4)))
    opt.tell(np.zeros(500))
    np.testing.assert_array_equal(opt.ask(), rng.uniform(-0.2, 0.2, size=(500, 4)))
    assert RandomSearch(2).params == RandomSearchParams()


def test_random_search_ranges_and_their_boundaries():
    RandomSearchParams(population=2, init_scale=1.0e6)
    RandomSearchParams(init_scale=1e-300)
    for kwargs, message in [
        ({"population": 0}, "population must be an integer in [2, 1000000], got 0"),
        ({"init_scale": 0.0}, "init_scale must be in (0, 1e+06], got 0.0"),
        ({"init_scale": 2.0e6}, "init_scale must be in (0, 1e+06], got 2000000.0"),
        ({"init_scale": np.inf}, "init_scale must be in (0, 1e+06], got inf"),
    ]:
        with pytest.raises(ValueError, match=exactly(message)):
            RandomSearchParams(**kwargs)
    assert RandomSearchParams().replace(population=3) == RandomSearchParams(3)


def test_random_search_state_keeps_the_best_and_is_checked():
    opt = RandomSearch(2, RandomSearchParams(population=3), 4)
    x = opt.ask()
    opt.tell([1.0, 3.0, 2.0])
    opt.ask()
    opt.tell([0.0, 0.0, 0.0])
    state = opt.state()
    np.testing.assert_array_equal(state["fitness"], [0.0, 0.0, 0.0])
    back = RandomSearch.from_state(2, RandomSearchParams(population=3), state)
    np.testing.assert_array_equal(back.best, x[1])
    assert back.best_fitness == 3.0 and back.fitness.dtype == np.float64
    np.testing.assert_array_equal(back.fitness, [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(back.ask(), opt.ask())
    with pytest.raises(
        ValueError, match=exactly("random-search state has the wrong shape")
    ):
        RandomSearch.from_state(
            2, RandomSearchParams(population=3), {**state, "generation": np.array(0)}
        )


def test_the_base_s_defaults_and_what_ask_accepts():
    opt = Fixed(3, RandomSearchParams(population=2))
    assert opt.seed == 0 and len(opt.fitness) == 0
    x = opt.ask()  # integers are asked as floats
    assert x.shape == (1, 3) and x.dtype == np.float64
    assert RandomSearch(2, RandomSearchParams(population=2)).seed == 0
    told = RandomSearch(2, RandomSearchParams(population=2), 3)
    told.ask()
    told.tell([1.0, 2.0])
    state = told.state()
    assert RandomSearch.from_state(2, RandomSearchParams(population=2), state).seed == 0


def test_random_search_s_init_scale_bound_is_exact_and_its_state_is_floats():
    with pytest.raises(ValueError, match="init_scale must be in"):
        RandomSearchParams(init_scale=1.0e6 + 0.5)
    opt = RandomSearch(2, RandomSearchParams(population=2), 0)
    opt.ask()
    opt.tell([1.0, 2.0])
    state = {**opt.state(), "fitness": np.array([1, 2])}
    back = RandomSearch.from_state(2, RandomSearchParams(population=2), state)
    assert back.fitness.dtype == np.float64
