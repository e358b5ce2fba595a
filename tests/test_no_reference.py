"""A behaviour that compares with no rule-based run (``reference_steps = 0``:
``Behaviour.reference`` gives None, as its docstring says) still reports its
metrics and its figure, without the ``rules_*`` numbers and the rule-based
curve. The type checker found the kick's and the successive jumping's
metrics and figures reading that reference unchecked: such a subclass of
either failed with ``AttributeError: 'NoneType' object has no attribute
'jumps'``."""

from __future__ import annotations

import numpy as np
import pytest

from locustjump.present.stages import reporter_of
from locustjump.present.stages.base import Episodes
from locustjump.tasks.kick import Kick
from locustjump.tasks.monolithic import Monolithic


class KickAlone(Kick):
    name = "kick-alone"
    reference_steps = 0


class MonolithicAlone(Monolithic):
    name = "monolithic-alone"
    reference_steps = 0


@pytest.mark.parametrize("cls", [KickAlone, MonolithicAlone])
def test_metrics_and_figure_without_a_reference(cls, params, tmp_path):
    alone, paper = cls(), cls.__mro__[1]()
    assert alone.reference(params) is None
    genome = alone.controller.random_genomes(np.random.default_rng(0), 1)
    res = alone.simulate(genome, params, record=alone.eval_record)

    got = alone.metrics(res, params, genome[0])
    assert got, "no metrics"
    assert not [k for k in got if "rules" in k], got
    # every other number is the behaviour's own, as with its reference
    full = paper.metrics(res, params, genome[0])
    assert got == {k: v for k, v in full.items() if "rules" not in k}
    assert list(got) == [k for k in full if "rules" not in k]  # same order

    (figure,) = reporter_of(paper).write_figures(
        Episodes(alone, res, params, None), tmp_path
    )
    assert figure.is_file() and figure.stat().st_size > 0
