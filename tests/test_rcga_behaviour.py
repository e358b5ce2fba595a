"""The RCGA's behaviour stated exactly: its settings' ranges and messages, each
operator's formula on scripted draws, the order of a generation's draws (which
fixes every shipped run), elitism, and the checks of a restored state.

Each test here was written against a mutant that the rest of the suite let
through (issue #48, scripts/mutation.py); docs/mutation.md lists the rest.
"""

import copy
import re

import numpy as np
import pytest

from locustjump.evo.rcga import (
    MAX_GENE_SCALE,
    RCGA,
    RCGAParams,
    blx_alpha,
    gaussian_mutation,
    sbx,
    tournament,
    undx,
)

GENE_SCALES = (
    "blx_alpha",
    "sbx_eta",
    "undx_sigma_xi",
    "undx_sigma_eta",
    "mutation_sigma",
    "init_scale",
)


class Scripted:
    """A stand-in for ``numpy.random.Generator`` whose draws are given: each
    call takes the next array of standard draws (uniform on [0, 1), normal
    N(0, 1) or integers) and applies the method's own arguments, as NumPy's
    do."""

    def __init__(self, *draws):
        self.draws = [np.asarray(d, dtype=np.float64) for d in draws]

    def _next(self, size):
        d = self.draws.pop(0)
        assert size is None or d.shape == tuple(np.atleast_1d(size)), (d.shape, size)
        return d

    def random(self, size=None):
        return self._next(size)

    def uniform(self, low=0.0, high=1.0, size=None):
        shape = np.broadcast(np.asarray(low), np.asarray(high)).shape
        return low + (high - low) * self._next(size or shape)

    def normal(self, loc=0.0, scale=1.0, size=None):
        return loc + scale * self._next(size)

    def integers(self, low, high=None, size=None):
        low, high = (0, low) if high is None else (low, high)
        d = self._next(size).astype(np.int64)
        assert ((low <= d) & (d < high)).all()
        return d


def exactly(message):
    return "^" + re.escape(message) + "$"


# --- settings ------------------------------------------------------------------


def test_the_boundaries_of_every_range_are_accepted():
    RCGAParams(population=2, elite=0, tournament_size=1)
    RCGAParams(population=2, elite=1)
    RCGAParams(crossover_rate=0.0, mutation_rate=0.0)
    RCGAParams(crossover_rate=1.0, mutation_rate=1.0)
    for name in GENE_SCALES:
        RCGAParams(**{name: 0.0})
        RCGAParams(**{name: MAX_GENE_SCALE})


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (
            {"population": 1, "elite": 0},
            ("population must be an integer in [2, 1000000], got 1"),
        ),
        ({"elite": -1}, "elite must be an integer in [0, 999999], got -1"),
        ({"elite": 50}, "elite must be less than population (50), got 50"),
        (
            {"tournament_size": 0},
            ("tournament_size must be an integer in [1, 1000000], got 0"),
        ),
        ({"crossover": "pmx"}, "crossover must be one of blx, sbx, undx, got 'pmx'"),
        ({"crossover_rate": -0.1}, "crossover_rate must be in [0, 1], got -0.1"),
        ({"mutation_rate": 1.5}, "mutation_rate must be in [0, 1], got 1.5"),
        ({"blx_alpha": -0.1}, "blx_alpha must be in [0, 1e+06], got -0.1"),
        ({"sbx_eta": np.inf}, "sbx_eta must be in [0, 1e+06], got inf"),
        ({"init_scale": np.nan}, "init_scale must be in [0, 1e+06], got nan"),
        (
            {"mutation_sigma": 2e6},
            "mutation_sigma must be in [0, 1e+06], got 2000000.0",
        ),
    ],
)
def test_a_setting_out_of_range_is_named_with_its_range(kwargs, message):
    with pytest.raises(ValueError, match=exactly(message)):
        RCGAParams(**kwargs)


def test_replace_changes_only_what_it_names():
    p = RCGAParams(population=30, crossover="sbx")
    q = p.replace(population=10)
    assert (q.population, q.crossover, q.elite) == (10, "sbx", p.elite)
    assert p.population == 30


# --- operators on scripted draws ----------------------------------------------


def test_blx_alpha_spreads_the_parents_box_by_alpha_on_each_side():
    a, b = np.array([[1.0, 5.0]]), np.array([[3.0, 4.0]])
    # uniform draws 0 and 1 land on the widened box's ends
    child = blx_alpha(a, b, 0.5, Scripted([[0.0, 0.999999]]))
    np.testing.assert_allclose(child, [[0.0, 5.5]], atol=1e-5)


def test_sbx_child_is_the_mean_plus_or_minus_half_beta_times_the_distance():
    # parents 1 and 3 (mean 2, distance 2), eta 1: beta = (2u)^(1/2) for
    # u <= 1/2, (1 / (2 (1 - u)))^(1/2) above; the second draw < 1/2 takes the
    # child on b's side: child = 2 +- beta
    a, b = np.full((1, 4), 1.0), np.full((1, 4), 3.0)
    u = [[0.25, 0.75, 0.25, 0.5]]
    side = [[0.3, 0.7, 0.7, 0.1]]
    child = sbx(a, b, 1.0, Scripted(u, side))
    beta = [np.sqrt(0.5), np.sqrt(2.0), np.sqrt(0.5), 1.0]
    np.testing.assert_allclose(child, [[2 + beta[0], 2 - beta[1], 2 - beta[2], 3.0]])
    # eta 2 at u = 1/16 and 15/16: beta = 1/2 and 2
    child = sbx(a[:, :2], b[:, :2], 2.0, Scripted([[1 / 16, 15 / 16]], [[0.1, 0.1]]))
    np.testing.assert_allclose(child, [[2.5, 4.0]])


def test_undx_moves_along_the_parents_axis_and_orthogonally_by_the_third():
    # a, b 2 apart along gene 0, c 3 off that line: D = 3
    a, b, c = np.array([[1.0, 1, 1]]), np.array([[3.0, 1, 1]]), np.array([[1.0, 4, 1]])
    xi, z = [[0.5]], [[1.0, 1.0, -1.0]]
    child = undx(a, b, c, 0.5, 0.35, Scripted(xi, z))
    k = 0.35 / np.sqrt(3) * 3.0  # sigma_eta / sqrt(P) * D; gene 0's part removed
    np.testing.assert_allclose(child, [[2.0 + 0.25 * 2.0, 1 + k, 1 - k]])
    # parents closer than 1: c's distance from their line is still exact
    a, b, c = np.zeros((1, 3)), np.array([[0.5, 0, 0]]), np.array([[0.5, 1.0, 0]])
    child = undx(a, b, c, 0.5, 0.35, Scripted([[0.0]], [[0.0, 1.0, 0.0]]))
    np.testing.assert_allclose(child, [[0.25, 0.35 / np.sqrt(3), 0.0]])


def test_gaussian_mutation_adds_sigma_times_a_normal_where_the_draw_is_below_rate():
    x = np.array([[1.0, 1.0, 1.0]])
    y = gaussian_mutation(x, 0.5, 0.2, Scripted([[0.1, 0.9, 0.3]], [[1.0, 1.0, -2.0]]))
    np.testing.assert_allclose(y, [[1.2, 1.0, 0.6]])


def test_tournament_returns_the_fittest_entrant_and_the_first_on_a_tie():
    fitness = np.array([0.0, 5.0, 5.0, 1.0])
    entrants = [[0, 3, 0], [2, 1, 0], [3, 0, 0]]
    np.testing.assert_array_equal(
        tournament(fitness, 3, 3, Scripted(entrants)), [3, 2, 3]
    )


# --- a generation ---------------------------------------------------------------


def reference_children(ga, n):
    """A generation's children as the RCGA's docstring and SPEC describe
    them, from a copy of its generator: two tournaments, the named crossover
    (UNDX takes a third tournament), the first parent kept with probability
    1 - crossover_rate (drawn only if that rate is below 1), then Gaussian
    mutation. This order of draws fixes every shipped run."""
    p, rng = ga.params, copy.deepcopy(ga.rng)

    def pick():
        return ga.population[tournament(ga.fitness, n, p.tournament_size, rng)]

    a, b = pick(), pick()
    if p.crossover == "blx":
        x = blx_alpha(a, b, p.blx_alpha, rng)
    elif p.crossover == "sbx":
        x = sbx(a, b, p.sbx_eta, rng)
    else:
        x = undx(a, b, pick(), p.undx_sigma_xi, p.undx_sigma_eta, rng)
    if p.crossover_rate < 1.0:
        keep = rng.random(n) >= p.crossover_rate
        x[keep] = a[keep]
    return gaussian_mutation(x, p.mutation_rate, p.mutation_sigma, rng)


@pytest.mark.parametrize("crossover", ["blx", "sbx", "undx"])
@pytest.mark.parametrize("rate", [1.0, 0.5])
def test_a_generation_draws_its_children_in_the_documented_order(crossover, rate):
    p = RCGAParams(population=8, elite=2, crossover=crossover, crossover_rate=rate)
    ga = RCGA(5, p, 11)
    for _ in range(3):
        x = ga.ask()
        ga.tell(-np.sum(x**2, axis=1))
        expected = reference_children(ga, 6)
        np.testing.assert_array_equal(ga.ask(), expected)


def test_without_crossover_each_child_is_its_first_parent():
    p = RCGAParams(population=20, elite=0, crossover_rate=0.0, mutation_rate=0.0)
    ga = RCGA(4, p, 5)
    ga.tell(-np.sum(ga.ask() ** 2, axis=1))
    children = ga.ask()
    rows = {tuple(r) for r in ga.population}
    assert all(tuple(c) in rows for c in children)


def test_with_half_crossover_about_half_the_children_are_copies():
    p = RCGAParams(population=400, elite=0, crossover_rate=0.5, mutation_rate=0.0)
    ga = RCGA(4, p, 5)
    ga.tell(-np.sum(ga.ask() ** 2, axis=1))
    rows = {tuple(r) for r in ga.population}
    copies = np.mean([tuple(c) in rows for c in ga.ask()])
    assert copies == pytest.approx(0.5, abs=0.08)


def test_the_first_population_is_uniform_in_init_scale_then_only_children_are_asked():
    p = RCGAParams(population=50, elite=3, init_scale=0.1)
    ga = RCGA(6, p)
    assert ga.seed == 0 and RCGA(6).params == RCGAParams()
    assert ga.population.shape == (0, 6)  # nothing told yet
    x = ga.ask()
    assert x.shape == (50, 6)
    assert np.abs(x).max() <= 0.1 and np.abs(x).max() > 0.09
    ga.tell(np.zeros(50))
    assert ga.ask().shape == (47, 6)


def test_a_given_initial_population_is_asked_first_as_floats():
    init = [[i, -i, 2 * i] for i in range(4)]
    ga = RCGA(3, RCGAParams(population=4, elite=1), 0, init)
    x = ga.ask()
    assert x.dtype == np.float64
    np.testing.assert_array_equal(x, np.array(init, dtype=float))
    with pytest.raises(
        ValueError, match=exactly("init has shape (2, 3), expected (4, 3)")
    ):
        RCGA(3, RCGAParams(population=4, elite=1), 0, init[:2])


# --- elitism ---------------------------------------------------------------------


def test_the_population_is_sorted_best_first_and_keeps_the_elites():
    p = RCGAParams(population=10, elite=2)
    ga = RCGA(3, p, 1)
    first = ga.ask()
    f = np.arange(10.0)
    ga.tell(f)
    np.testing.assert_array_equal(ga.fitness, f[::-1])
    np.testing.assert_array_equal(ga.population, first[::-1])
    elites = ga.population[:2].copy()
    for _ in range(3):  # children all worse: the elites stay, first
        ga.ask()
        ga.tell(np.full(8, -1.0))
        np.testing.assert_array_equal(ga.population[:2], elites)
        np.testing.assert_array_equal(ga.fitness[:3], [9.0, 8.0, -1.0])
        assert ga.best_fitness == 9.0


def test_elites_win_ties_and_tied_children_keep_their_order():
    p = RCGAParams(population=10, elite=2)
    ga = RCGA(3, p, 1)
    ga.ask()
    ga.tell(np.array([1.0, 1.0, 0, 0, 0, 0, 0, 0, 0, 0]))
    elites = ga.population[:2].copy()
    children = ga.ask()
    ga.tell(np.array([1.0, 0, 1, 0, 1, 0, 1, 0]))
    order = [0, 2, 4, 6]  # the children told 1.0, in the order told
    np.testing.assert_array_equal(ga.population[:2], elites)
    np.testing.assert_array_equal(ga.population[2:6], children[order])
    np.testing.assert_array_equal(ga.population[6:], children[[1, 3, 5, 7]])


# --- checkpoints -------------------------------------------------------------------


def state_of(generation, population, fitness, seed=0):
    ga = RCGA(population.shape[1], RCGAParams(population=len(population)), seed)
    return {
        **ga.state(),  # generation 0: its generator
        "generation": np.array(generation),
        "population": population,
        "fitness": fitness,
    }


def test_a_restored_state_restores_the_best_from_its_first_row():
    pop = np.arange(12.0).reshape(4, 3)
    fit = np.array([3.0, 2.0, 1.0, 0.0])
    ga = RCGA.from_state(3, RCGAParams(population=4), state_of(1, pop, fit))
    np.testing.assert_array_equal(ga.best, pop[0])
    assert ga.best_fitness == 3.0 and ga.generation == 1


def test_a_state_of_integers_is_restored_as_floats():
    pop = np.arange(12).reshape(4, 3)
    ga = RCGA.from_state(
        3, RCGAParams(population=4), state_of(2, pop, np.array([3, 2, 1, 0]))
    )
    assert ga.population.dtype == np.float64 and ga.fitness.dtype == np.float64


@pytest.mark.parametrize(
    "generation, pop, fit, message",
    [
        (0, (4, 3), 4, "population has shape (4, 3) at generation 0, expected (4, 3)"),
        (1, (5, 3), 4, "population has shape (5, 3) at generation 1, expected (4, 3)"),
        (1, (4, 2), 4, "population has shape (4, 2) at generation 1, expected (4, 3)"),
        (1, (4, 3), 5, "fitness has the wrong shape or contains NaN"),
        (1, (4, 3), "nan", "fitness has the wrong shape or contains NaN"),
        (1, "inf", 4, "population is not finite"),
    ],
)
def test_an_inconsistent_state_is_refused_with_what_is_wrong(
    generation, pop, fit, message
):
    population = np.zeros((4, 3)) if isinstance(pop, str) else np.zeros(pop)
    if pop == "inf":
        population[1, 2] = np.inf
    fitness = np.zeros(4) if isinstance(fit, str) else np.zeros(fit)
    if fit == "nan":
        fitness[2] = np.nan
    with pytest.raises(ValueError, match=exactly(message)):
        RCGA.from_state(
            3, RCGAParams(population=4), state_of(generation, population, fitness)
        )
