"""The QD optimizers' settings and their state (evo/qd.py, evo/map_elites.py,
evo/cma_me.py), each rule by its exact message; fast (MAP-Elites only runs)."""

import sys

import numpy as np
import pytest

from locustjump.evo import CMAMEParams, MapElites, MapElitesParams
from locustjump.evo.qd import DEFAULT_CELLS, MAX_CELLS, import_ribs

pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")

GRID = {"descriptors": ("a", "b"), "ranges": ((0.0, 1.0), (-1.0, 1.0))}
DECLARED = {"a": (0.0, 2.0), "b": (-1.0, 3.0), "c": (5.0, 6.0)}


def _message(make):
    with pytest.raises(ValueError) as err:
        make()
    return str(err.value)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"population": 2, "emitters": 3},
         "population must be >= 1 per emitter (3 emitters: >= 3), got 2"),
        ({"descriptors": ("a", "b", "a")},
         "descriptors repeat a name: ['a', 'b', 'a']"),
        ({"ranges": ((0.0, 1.0), (1.0, 1.0))},
         "ranges must be finite (low, high) with low < high, got "
         "[[0.0, 1.0], [1.0, 1.0]]"),
        ({"ranges": ((2.0, 1.0),)},
         "ranges must be finite (low, high) with low < high, got [[2.0, 1.0]]"),
        ({"ranges": ((np.nan, 1.0),)},
         "ranges must be finite (low, high) with low < high, got [[nan, 1.0]]"),
        ({"ranges": ((0.0, np.inf),)},
         "ranges must be finite (low, high) with low < high, got [[0.0, inf]]"),
        ({"cells": (3, 0)}, "cells must be >= 1 each, got [3, 0]"),
        ({"cells": (-1,)}, "cells must be >= 1 each, got [-1]"),
        ({"cells": (101, 100)}, "cells [101, 100] make 10,100 cells; at most 10,000"),
        ({**GRID, "cells": (4,)}, "cells has 1 entries for 2 descriptors (a, b)"),
        ({"descriptors": ("a",), "ranges": GRID["ranges"]},
         "ranges has 2 entries for 1 descriptors (a)"),
        ({"variation": "line"},
         "variation must be one of gaussian, iso-line, got 'line'"),
    ],
)  # fmt: skip
def test_bad_settings_are_refused_saying_what_is_wrong(kwargs, message):
    assert _message(lambda: MapElitesParams(**kwargs)) == message


def test_settings_at_their_limits_are_taken():
    assert MapElitesParams(population=3, emitters=3).batch_sizes() == [1, 1, 1]
    assert MapElitesParams(cells=(100, 100)).cells == (100, 100)
    assert MAX_CELLS == 10_000
    assert MapElitesParams(cells=(1,)).cells == (1,)
    assert MapElitesParams(descriptors=("a",), cells=(3,)).cells == (3,)
    # ranges and cells may be left to the task
    assert MapElitesParams(descriptors=("a", "b")).ranges == ()
    # CMA-ME's emitters rank: two genomes each at least
    assert CMAMEParams(population=10, emitters=5).batch_sizes() == [2] * 5
    assert _message(lambda: CMAMEParams(population=9, emitters=5)) == (
        "population must be >= 2 per emitter (5 emitters: >= 10), got 9"
    )


@pytest.mark.parametrize(
    ("population", "emitters", "sizes"),
    [(50, 1, [50]), (50, 3, [17, 17, 16]), (7, 3, [3, 2, 2]), (9, 4, [3, 2, 2, 2])],
)
def test_the_population_is_shared_the_first_emitters_taking_one_more(
    population, emitters, sizes
):
    assert MapElitesParams(population=population, emitters=emitters).batch_sizes() == (
        sizes
    )


def test_the_task_fills_what_the_settings_leave_out():
    p = MapElitesParams().with_task("kick", DECLARED, ("b", "a"))
    assert p.descriptors == ("b", "a")
    assert p.ranges == ((-1.0, 3.0), (0.0, 2.0))
    assert p.cells == (DEFAULT_CELLS, DEFAULT_CELLS) == (10, 10)
    assert isinstance(p, MapElitesParams) and p.population == 50
    # what the settings say stays
    q = MapElitesParams(descriptors=("c",), ranges=((0.0, 9.0),), cells=(4,))
    q = q.with_task("kick", DECLARED, ("a", "b"))
    assert (q.descriptors, q.ranges, q.cells) == (("c",), ((0.0, 9.0),), (4,))
    r = MapElitesParams(descriptors=("c", "a")).with_task("kick", DECLARED, ("b",))
    assert r.ranges == ((5.0, 6.0), (0.0, 2.0)) and r.cells == (10, 10)


def test_a_task_that_cannot_fill_them_is_named():
    m = MapElitesParams()
    assert _message(lambda: m.with_task("getup", {}, ())) == (
        "the map-elites optimizer needs behaviour descriptors and getup declares none"
    )
    assert _message(lambda: CMAMEParams().with_task("getup", {}, ())) == (
        "the cma-me optimizer needs behaviour descriptors and getup declares none"
    )
    assert _message(lambda: m.with_task("kick", DECLARED, ("a", "z", "y"))) == (
        "unknown descriptor 'z'; kick declares a, b, c"
    )
    bad = MapElitesParams(cells=(3,))
    assert _message(lambda: bad.with_task("kick", DECLARED, ("a", "b"))) == (
        "cells has 1 entries for 2 descriptors (a, b)"
    )


def test_an_optimizer_needs_its_grid():
    for p in (
        MapElitesParams(),
        MapElitesParams(**GRID),
        MapElitesParams(descriptors=GRID["descriptors"], cells=(2, 2)),
    ):
        assert _message(lambda p=p: MapElites(3, p, 0)) == (
            "the map-elites optimizer needs its descriptors, their ranges and "
            "cells (TrainConfig fills them from the task)"
        )


def _problem(x):
    return -np.sum((x - 0.3) ** 2, axis=1), np.clip(np.abs(x[:, :2]), 0, 1)


def _opt(seed=1, **kw):
    return MapElites(4, MapElitesParams(population=6, cells=(3, 4), **GRID, **kw), seed)


def test_it_is_told_descriptors_or_nothing():
    opt = _opt()
    x = opt.ask()
    with pytest.raises(TypeError) as err:
        opt._tell(x, _problem(x)[0])
    assert str(err.value) == "the map-elites optimizer is told descriptors too"
    assert opt.descriptor_names == ("a", "b")


def test_the_archive_and_the_diagnostics_are_pyribs_grid():
    opt = _opt(qd_offset=-1.0)
    d = opt.diagnostics()
    assert d["qd_score"] == 0.0 and d["coverage"] == 0.0 and np.isnan(d["archive_best"])
    found = []
    for g in range(3):
        x = opt.ask()
        f, m = _problem(x)
        opt.tell(f, m)
        found.append((x, f, m, g + 1))
    a = opt.archive()
    grid = opt._grid.data()
    assert a.names == ("a", "b") and a.dims == (3, 4)
    np.testing.assert_array_equal(a.lows, [0.0, -1.0])
    np.testing.assert_array_equal(a.highs, [1.0, 1.0])
    for k in ("index", "solution", "objective", "measures", "generation"):
        np.testing.assert_array_equal(getattr(a, k), grid[k])
        assert getattr(a, k).dtype == (np.int64 if k in ("index", "generation")
                                       else np.float64)  # fmt: skip
    # each elite is a genome told, with its fitness, descriptors and generation
    for pos in range(len(a)):
        hit = [
            (g, i) for x, f, m, g in found for i in range(len(x))
            if np.array_equal(x[i], a.solution[pos])
        ]  # fmt: skip
        (g, i), *_ = hit
        x, f, m, _ = found[g - 1]
        assert a.objective[pos] == f[i] and a.generation[pos] == g
        np.testing.assert_array_equal(a.measures[pos], m[i])
    d = opt.diagnostics()
    assert d["coverage"] == len(a) / 12 == a.coverage
    assert d["archive_best"] == a.objective.max() == opt.best_fitness
    assert d["qd_score"] == pytest.approx(a.qd_score(offset=-1.0), rel=1e-12)
    assert d["qd_score"] == pytest.approx(np.sum(a.objective + 1.0), rel=1e-12)


def test_the_state_is_the_seed_what_was_told_and_the_archive():
    opt = _opt()
    told = []
    for _ in range(2):
        x = opt.ask()
        f, m = _problem(x)
        opt.tell(f, m)
        told.append((f, m))
    s = opt._state()
    assert int(s["seed"]) == 1
    np.testing.assert_array_equal(s["fitness_history"], [t[0] for t in told])
    np.testing.assert_array_equal(s["descriptor_history"], [t[1] for t in told])
    assert s["descriptor_history"].shape == (2, 6, 2)
    a = opt.archive()
    for k in ("index", "solution", "objective", "measures", "generation"):
        np.testing.assert_array_equal(s[f"archive_{k}"], getattr(a, k))
    again = _opt()
    again.load_state(opt.state())
    np.testing.assert_array_equal(again.ask(), opt.ask())


def test_a_state_of_another_seed_or_shape_is_refused():
    opt = _opt()
    x = opt.ask()
    opt.tell(*_problem(x))
    state = opt.state()
    assert _message(lambda: _opt(seed=2).load_state(state)) == (
        "state is of seed 1, not 2"
    )
    for key, bad in (
        ("fitness_history", np.zeros((1, 5))),
        ("descriptor_history", np.zeros((1, 6, 3))),
    ):
        broken = {**state, key: bad}
        message = _message(lambda b=broken: _opt().load_state(b))
        f = "(1, 5)" if key == "fitness_history" else "(1, 6)"
        m = "(1, 6, 3)" if key == "descriptor_history" else "(1, 6, 2)"
        assert message == (
            f"fitness_history {f} and descriptor_history {m} are not 1 "
            "generations of 6 genomes and 2 descriptors"
        )


@pytest.mark.parametrize("key", ["index", "solution", "objective", "measures",
                                 "generation"])  # fmt: skip
def test_a_state_whose_archive_differs_from_its_replay_is_refused(key):
    opt = _opt()
    for _ in range(2):
        x = opt.ask()
        opt.tell(*_problem(x))
    state = opt.state()
    assert len(state[f"archive_{key}"]) > 1  # something to break
    for bad in (state[f"archive_{key}"][:-1], state[f"archive_{key}"][::-1].copy()):
        if np.array_equal(bad, state[f"archive_{key}"]):
            continue
        broken = {**state, f"archive_{key}": bad}
        assert _message(lambda b=broken: _opt().load_state(b)) == (
            f"archive_{key} is not what replaying its history gives "
            "(written by another pyribs?)"
        )


def test_pyribs_is_found():
    ribs = import_ribs()
    assert hasattr(ribs.archives, "GridArchive")


def test_without_pyribs_the_extra_is_named(monkeypatch):
    monkeypatch.setitem(sys.modules, "ribs.schedulers", None)
    with pytest.raises(ImportError) as err:
        import_ribs()
    assert str(err.value) == (
        "the quality-diversity optimizers need pyribs: pip install -e '.[qd]' "
        "in the clone"
    )


def _seeds(seed, emitters):
    return [int(s) for s in np.random.SeedSequence(seed).generate_state(1 + emitters)]


def _same_generator(rng, seed):
    return rng.bit_generator.state == np.random.default_rng(seed).bit_generator.state


def test_the_archive_is_a_grid_seeded_from_the_runs_seed():
    opt = _opt(seed=7, qd_offset=-2.5)
    grid = opt._grid
    assert type(grid).__name__ == "GridArchive" and grid.solution_dim == 4
    assert grid.dims.tolist() == [3, 4] and grid.qd_score_offset == -2.5
    np.testing.assert_array_equal(grid.lower_bounds, [0.0, -1.0])
    np.testing.assert_array_equal(grid.upper_bounds, [1.0, 1.0])
    assert grid.dtypes["generation"] == np.int64
    assert _same_generator(grid._rng, _seeds(7, 1)[0])
    assert opt._scheduler.archive is grid


@pytest.mark.parametrize("variation", ["gaussian", "iso-line"])
def test_map_elites_emitters_start_uniform_and_vary_as_set(variation):
    p = MapElitesParams(population=7, emitters=3, cells=(3, 4), variation=variation,
                        sigma=0.03, line_sigma=0.4, init_scale=0.5, **GRID)  # fmt: skip
    opt = MapElites(4, p, seed=5)
    first = np.random.default_rng(5).uniform(-0.5, 0.5, (7, 4))
    emitters = opt._scheduler.emitters
    name = "GaussianEmitter" if variation == "gaussian" else "IsoLineEmitter"
    assert [type(e).__name__ for e in emitters] == [name] * 3
    seeds = _seeds(5, 3)[1:]
    for e, start, stop, seed in zip(emitters, (0, 3, 5), (3, 5, 7), seeds, strict=True):
        assert e.batch_size == stop - start and e.archive is opt._grid
        np.testing.assert_array_equal(e.initial_solutions, first[start:stop])
        assert _same_generator(e._rng, seed)
        if variation == "gaussian":
            np.testing.assert_array_equal(e.sigma, 0.03)
        else:
            assert (e.iso_sigma, e.line_sigma) == (0.03, 0.4)
    np.testing.assert_array_equal(opt.ask(), first)


def test_cma_me_emitters_are_cma_es_ranked_by_improvement():
    from locustjump.evo import CMAME

    p = CMAMEParams(population=7, emitters=3, sigma0=0.25, cells=(3, 4), **GRID)
    opt = CMAME(4, p, seed=5)
    emitters = opt._scheduler.emitters
    assert [type(e).__name__ for e in emitters] == ["EvolutionStrategyEmitter"] * 3
    for e, n, seed in zip(emitters, (3, 2, 2), _seeds(5, 3)[1:], strict=True):
        assert e.batch_size == n and e.archive is opt._grid
        np.testing.assert_array_equal(e.x0, np.zeros(4))
        assert e._sigma0 == 0.25
        assert type(e._ranker).__name__ == "TwoStageImprovementRanker"
        assert type(e._opt).__name__ == "CMAEvolutionStrategy"
        assert (e._selection_rule, e._restart_rule) == ("filter", "no_improvement")
        # pyribs spawns the evolution strategy's generator from the seed
        opt_seed = np.random.SeedSequence(seed).spawn(2)[0]
        assert _same_generator(e._opt._rng, opt_seed)


def test_seed_0_is_the_default_and_integer_ranges_read_as_floats():
    p = MapElitesParams(population=6, descriptors=("a", "b"), ranges=((0, 1), (-1, 1)),
                        cells=(3, 4))  # fmt: skip
    np.testing.assert_array_equal(MapElites(4, p).ask(), MapElites(4, p, 0).ask())
    a = MapElites(4, p).archive()
    assert a.lows.dtype == a.highs.dtype == np.float64
    np.testing.assert_array_equal(a.edges(1), [-1.0, -0.5, 0.0, 0.5, 1.0])
