"""The table's "gain in the last third": the share of a run's whole
improvement (its best so far, first generation to last) made in its last
third of generations."""

import numpy as np
import pytest

from locustjump.runs.learning import flat_note, late_gain


def test_an_elitist_curve():
    # 9 generations: the last third is generations 7-9, measured from gen 6
    best = np.array([1.0, 2, 3, 4, 5, 8, 8, 9, 10])
    assert late_gain(best) == pytest.approx((10 - 8) / (10 - 1))
    assert late_gain(np.full(9, 5.0)) == 0.0  # never improved
    # 183 generations (the debris study's one network): from generation 122
    best = np.arange(1.0, 184.0)
    assert late_gain(best) == pytest.approx((183 - 122) / (183 - 1))
    # an offset changes nothing: a share of the improvement
    assert late_gain(best + 1000.0) == pytest.approx(late_gain(best))


def test_without_an_elite_the_curve_is_the_best_so_far():
    """Random search's best of a generation falls as often as it rises: a
    generation worse than an earlier one loses nothing that was found."""
    best = np.array([1.0, 9, 2, 3, 4, 2, 5, 3, 1])
    assert late_gain(best) == 0.0  # 9 was found in generation 2
    best = np.array([1.0, 2, 3, 4, 5, 6, 2, 7, 3])
    assert late_gain(best) == pytest.approx((7 - 6) / (7 - 1))


def test_negative_fitness_and_short_runs():
    # fitness below zero (return-legs): from -4 to -1, the last 0.5 of 3 late
    best = np.array([-4.0, -3, -2, -2, -2, -1.5, -1.5, -1.2, -1])
    assert late_gain(best) == pytest.approx(0.5 / 3)
    assert late_gain(np.array([1.0, 2.0])) == 0.0  # no third to speak of
    assert late_gain(np.array([0.0, 0.0, 0.0])) == 0.0  # nothing gained
    # three generations are enough: the last third is the last one
    assert late_gain(np.array([1.0, 2.0, 3.0])) == pytest.approx(0.5)
    # a gain below 1 in fitness units counts as a gain
    assert late_gain(np.array([0.0, 0.1, 0.2, 0.3, 0.4, 0.5])) == pytest.approx(0.4)


def test_the_flattening_rule_marks_each_arm_and_reads_at_its_limit():
    arms = {
        "p": {"label": "pipeline", "budget": {"late_gain": 0.0504}},
        "m": {"label": "one network", "budget": {"late_gain": 0.05}},
        "z": {"label": "still", "budget": {"late_gain": 0.0}},
    }
    note = flat_note(0.05, arms)
    assert note == (
        "Flat by the study's declared rule (the median gain in the last third at "
        "most 5.00%): pipeline no (5.04%); one network yes (5.00%); still yes (0.00%)."
    )
    assert [a["flat"] for a in arms.values()] == [False, True, True]
    assert all(type(a["flat"]) is bool for a in arms.values())  # JSON-able
