"""``scripts/contact_budget.py`` (what ``scripts/wall_takeoff.py`` reports):
a recorded episode replayed open loop matches the engine bit for bit, and
its contact impulses close the momentum budget. On the flat floor's highest
kick (``results/study/kick-apex-cma-s0``, 12 substeps): a second of physics."""

import dataclasses
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from locustjump import rundir
from locustjump.sim.analysis import clearance
from locustjump.sim.engine.backends import ThreadBackend

REPO = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "contact_budget", REPO / "scripts" / "contact_budget.py"
)
cb = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("contact_budget", cb)  # its dataclasses look it up
_spec.loader.exec_module(cb)


@pytest.fixture(scope="module")
def ceiling():
    cfg, beh, best = rundir.load_run(REPO / "results/study/kick-apex-cma-s0")
    p = dataclasses.replace(cfg.model, substeps=12)
    with ThreadBackend(1) as backend:
        r = cb.simulate(beh, best.genome, cfg.engine, beh.terrains.scene, p, backend)
    apex = int(np.argmax(clearance(r.rec["qpos"], p, r.here.scene)))
    return r, apex, cb.replay(r, 0, apex)


def test_the_replay_is_the_engines_episode(ceiling):
    r, apex, tr = ceiling
    assert apex == 83  # docs/science.md's flat ceiling: apex at step 83
    assert tr.deviation == 0.0 and tr.obs_equal and tr.wall_mismatch == []
    assert len(tr.meters) == apex and tr.momentum.shape == (apex + 1, 3)
    assert tr.gap.shape == (apex,) and np.isinf(tr.gap).all()  # no wall here


def test_the_impulses_close_the_momentum_budget(ceiling):
    r, apex, tr = ceiling
    axes = cb.axes_for(0.0, walls=False)
    b = cb.budget("flat", tr, r.rec["qpos"], 0, apex, axes)
    up = b.by_class[:, 0].sum() + b.gravity
    assert b.gravity == pytest.approx(-tr.weight * apex / 120)
    assert up == pytest.approx(b.change[0], abs=0.01)  # N s, of a 9 N s push
    assert b.by_class[0, 0] > 8.5 and not b.by_class[1:].any()  # floor only
    horizontal = b.by_class[:, 1:].sum(axis=0)
    assert horizontal == pytest.approx(b.change[1:], abs=0.01)
    assert cb.take_off(tr, apex) == 14
    assert b.rise == pytest.approx(1.933, abs=0.001)
