"""What ``evaluate`` reports of a re-simulated genome
(:mod:`locustjump.present.evaluate`): whether it matches its record, the
held-out fitness and the generalisation gap over terrains, and its JSON."""

import json
from pathlib import Path

import numpy as np
import pytest

from locustjump.present.evaluate import Evaluation, TerrainEvaluation, plain


def _ev(**kw):
    args = {"behaviour": "kick", "fitness": 1.5, "recorded_fitness": 1.5,
            "metrics": {"jumps": 2}, "files": [Path("e/t.csv")]}  # fmt: skip
    args.update(kw)
    return Evaluation(**args)


def test_an_evaluation_matches_its_record_bit_for_bit():
    assert _ev().matches
    assert not _ev(fitness=np.nextafter(1.5, 2)).matches
    assert _ev(fitness=0.0, elsewhere=True).matches  # another scene: no record
    d = {"a": 1.0}
    assert _ev(descriptors=d, recorded_descriptors=dict(d)).matches
    assert not _ev(descriptors=d, recorded_descriptors={"a": 1.5}).matches
    assert not _ev(descriptors=d).matches


def test_an_evaluation_as_json():
    assert _ev().to_dict() == {
        "behaviour": "kick", "fitness": 1.5, "recorded_fitness": 1.5,
        "fitness_matches": True, "other_scene": False,
        "metrics": {"jumps": 2}, "files": ["e/t.csv"],
    }  # fmt: skip
    e = _ev(fitness=2.0, elsewhere=True, descriptors={"a": 1.0},
            recorded_descriptors={"a": 0.5})  # fmt: skip
    d = e.to_dict()
    assert list(d) == ["behaviour", "fitness", "recorded_fitness", "fitness_matches",
                       "other_scene", "descriptors", "recorded_descriptors",
                       "metrics", "files"]  # fmt: skip
    assert d["descriptors"] == {"a": 1.0} and d["recorded_descriptors"] == {"a": 0.5}
    assert d["fitness_matches"] is True and d["other_scene"] is True
    assert json.loads(json.dumps(d)) == d


def test_numpy_values_become_pythons_own():
    value = {"a": np.float64(1.5), "b": [np.int64(2), (np.bool_(True), "x")],
             "c": np.arange(3), "d": None, "e": {"f": np.float32(0.5)}}  # fmt: skip
    out = plain(value)
    assert out == {"a": 1.5, "b": [2, (True, "x")], "c": [0, 1, 2], "d": None,
                   "e": {"f": 0.5}}  # fmt: skip
    assert type(out["a"]) is float and type(out["b"][0]) is int
    assert type(out["b"][1]) is tuple and type(out["b"][1][0]) is bool
    assert type(out["c"]) is list and type(out["e"]["f"]) is float
    json.dumps(out)


def _te(fitness, trained, aggregate="mean", train=3.0):
    n = len(fitness)
    return TerrainEvaluation("kick", "debris", list(range(100, 100 + n)), fitness,
                             trained, [{"i": i} for i in range(n)], train,
                             aggregate)  # fmt: skip


def test_the_held_out_fitness_is_combined_as_training_combined_it():
    t = _te([1.0, 2.0, 4.0, 9.0], [True, False, False, True])
    assert t.held_out == 3.0 and type(t.held_out) is float
    assert t.gap == 0.0
    m = _te([1.0, 2.0, 4.0, 9.0], [True, False, False, True], "min", train=5.0)
    assert m.held_out == 2.0 and m.gap == 3.0
    assert _te([1.0, -2.0], [False, False], train=1.0).gap == 1.5
    seen = _te([1.0, 2.0], [True, True])
    assert seen.held_out is None and seen.gap is None


def test_terrains_as_json():
    t = _te([1.0, 2.0], [True, False], "min", train=2.5)
    assert t.to_dict() == {
        "behaviour": "kick", "scene": "debris", "aggregate": "min",
        "train_fitness": 2.5, "held_out_fitness": 2.0,
        "generalisation_gap": 0.5,
        "terrains": [
            {"seed": 100, "fitness": 1.0, "trained": True, "metrics": {"i": 0}},
            {"seed": 101, "fitness": 2.0, "trained": False, "metrics": {"i": 1}},
        ],
    }  # fmt: skip


def test_terrains_of_unequal_lists_are_refused_not_cut_short():
    t = _te([1.0, 2.0], [True, False])
    t.metrics.pop()
    with pytest.raises(ValueError):
        t.to_dict()
