"""The pieces of ``results.md`` that read no directory (``present/results.py``):
its numbers and spreads, the budget table, why failing claims fail, and the
section on terrains training never saw."""

import pytest

from locustjump.present import results as rs
from locustjump.present.stages.base import Claim


@pytest.mark.parametrize(
    ("s", "said"), [(0, "0 s"), (59.4, "59 s"), (60, "1.0 min"), (754, "12.6 min")]
)
def test_minutes(s, said):
    assert rs.minutes(s) == said


def test_numbers_and_spreads():
    assert (rs._num(3.0), rs._num(3), rs._num(2.345), rs._num(-1.0)) == (
        "3", "3", "2.35", "-1",
    )  # fmt: skip
    assert rs._spread([]) == "n/a"
    assert rs._spread([5]) == "5 [5, 5]"
    assert rs._spread([1, 2, 10, 4]) == "3 [1, 10]"
    assert rs._spread([0.5, 1.25, 3]) == "1.25 [0.50, 3]"


@pytest.mark.parametrize(
    ("seeds", "said"),
    [
        ([100, 101, 102], "100-102"),
        ([3, 4], "3, 4"),  # two are listed, not a range
        ([7], "7"),
        ([1, 2, 4], "1, 2, 4"),
        ([2, 1, 0], "2, 1, 0"),
    ],
)
def test_seeds_as_a_range_or_a_list(seeds, said):
    assert rs._seeds(seeds) == said


def test_the_budget_table():
    info = {
        "kick": {"generations": 30, "evaluations": 1500, "control_steps": 1234567,
                 "train_wall_s": 90.0, "eval_wall_s": 4.0},
        "getup": {"generations": 10, "evaluations": 500, "control_steps": 20000,
                  "train_wall_s": 30.0, "eval_wall_s": 1.0},
    }  # fmt: skip
    lines = rs._budget_table({"population": 50}, {"wall_s": 5.0}, info)
    assert lines == [
        "## Budget and wall time",
        "",
        "| stage | population | generations | genome evaluations | control steps | "
        "training wall time | evaluation |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        "| rules | - | - | - | 3,000 | - | 5 s |",
        "| kick | 50 | 30 | 1,500 | 1,234,567 | 1.5 min | 4 s |",
        "| getup | 50 | 10 | 500 | 20,000 | 30 s | 1 s |",
        "| **total** | | | | | 2.2 min | |",  # 5 + 94 + 31 s
        "",
        "Training wall time is the sum of the per-generation times in each "
        "stage's `metrics.csv` (exact across interruptions).",
        "",
    ]


def test_why_failing_claims_fail_once_each():
    a = Claim("a", "1", reason="it fell", why="a study says so")
    b = Claim("b", "2", reason="it stood")
    c = Claim("c", "3", why="known")
    d = Claim("d", "4")  # nothing known: not listed
    assert rs._whys([a, b, a, c, d]) == [
        "Why the failing claims fail:",
        "",
        "- **a**: this run: it fell; beyond this run: a study says so.",
        "- **b**: this run: it stood.",
        "- **c**: beyond this run: known.",
        "",
    ]
    assert rs._whys([a, b, c], this_run=False) == [
        "Why the failing claims fail:",
        "",
        "- **a**: beyond this run: a study says so.",
        "- **c**: beyond this run: known.",
        "",
    ]
    assert rs._whys([b], this_run=False) == [] and rs._whys([]) == []


def _terrain(seed, fitness, trained=False, **metrics):
    return {"seed": seed, "fitness": fitness, "trained": trained, "metrics": metrics}


def test_the_section_on_held_out_terrains():
    kick = {
        "scene": "debris", "aggregate": "mean", "train_fitness": 12.3456,
        "held_out_fitness": 10.0, "generalisation_gap": 2.3456,
        "terrains": [
            _terrain(0, 12.0, trained=True, jumps=9),
            _terrain(100, 9.0, jumps=1, overturned=0, recovered=0),
            _terrain(101, 10.0, jumps=2, overturned=2, recovered=1),
            _terrain(102, 11.0, jumps=4, overturned=1, recovered=1),
        ],
    }  # fmt: skip
    held = [
        _terrain(100, 5.0),
        _terrain(101, 6.0, jumps=1),
        _terrain(102, 7.0, jumps=2),
    ]
    bare = {
        **kick,
        "train_fitness": 5.0,
        "held_out_fitness": 6.0,
        "generalisation_gap": -1.0,
        "terrains": [_terrain(0, 1.0, trained=True), *held],
    }
    assert rs.held_out_markdown({"kick": kick, "getup": bare}) == [
        "## On terrains training never saw",
        "",
        "Each best genome re-scored on debris terrains 100-102, none of them a "
        "training terrain (`locustjump evaluate DIR --terrain-seeds 100-102` "
        "prints them one by one). Held out: the training aggregate (mean) over "
        "them; gap: the training fitness minus it.",
        "",
        "| controller | training fitness | held out | per terrain: median [min, max] "
        "| gap | jumps | overturned / recovered |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        "| kick | 12.35 | 10 | 10 [9, 11] | +2.346 | 2 [1, 4] | 1 [0, 2] / 1 [0, 1] |",
        "| getup | 5 | 6 | 6 [5, 7] | -1 | n/a | n/a |",
        "",
        "Jumps and falls: median [min, max] over the held-out terrains.",
        "",
    ]


def test_held_out_terrains_listed_and_none():
    two = {"scene": "debris", "aggregate": "min", "train_fitness": 1.0,
           "held_out_fitness": 1.0, "generalisation_gap": 0.0,
           "terrains": [_terrain(5, 1.0), _terrain(9, 1.0, jumps=True)]}  # fmt: skip
    lines = rs.held_out_markdown({"kick": two})
    assert "terrains 5, 9, none of them" in lines[2]
    assert "--terrain-seeds 5,9` prints" in lines[2] and "aggregate (min)" in lines[2]
    assert lines[6] == "| kick | 1 | 1 | 1 [1, 1] | +0 | n/a | n/a |"
    trained_only = {**two, "terrains": [_terrain(0, 1.0, trained=True)]}
    assert rs.held_out_markdown({"kick": trained_only}) == []
    assert rs.held_out_markdown({}) == []
