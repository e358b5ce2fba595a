"""How far the rule-based jumper got (:mod:`locustjump.tasks.reference`):
the outcome of a made-up episode stated whole, and the head of a run."""

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.analysis import JUMP_THRESHOLD_BL, STUCK_S, Jump
from locustjump.sim.scene import Debris, Flat
from locustjump.tasks.reference import RulesRun, rules_outcome

P = lm.LocustParams()
T = 600  # control steps: 5 s


def _run(stuck_from=None, jumps=(10, 200, 400)):
    qpos = np.zeros((T + 1, 7 + 4))
    qpos[:, 0] = 0.25 + np.arange(T + 1) * 0.001  # 1 mm a step along x
    qpos[:, 1] = -0.5
    qpos[:, 2] = 0.1
    obs = np.zeros((T + 1, 9))
    obs[:, 8] = 1.0
    if stuck_from is not None:
        obs[stuck_from:, 8] = -0.5
    obs[-1, 8] = obs[-2, 8] * 0.75
    found = [Jump(s, s + 5, s + 10, 0.2, 0.0, 0.1) for s in jumps]
    return RulesRun(qpos, obs, np.zeros((T + 1, 4)), found, 0.3, False)


def test_an_episode_that_never_lies_overturned():
    assert rules_outcome(_run(), P) == {
        "jumps": 3, "stuck_overturned_s": None, "jumps_before_stuck": 3,
        "distance_m": pytest.approx(T * 0.001, abs=1e-15), "final_up_z": 0.75,
    }  # fmt: skip


def test_an_episode_that_lies_overturned_for_good():
    out = rules_outcome(_run(stuck_from=300), P)
    assert out["stuck_overturned_s"] == 300 * lm.CONTROL_DT
    assert out["jumps_before_stuck"] == 2 and out["jumps"] == 3
    assert out["distance_m"] == pytest.approx(300 * 0.001, abs=1e-15)
    assert out["final_up_z"] == -0.375
    at = rules_outcome(_run(stuck_from=400), P)  # a jump starting there: after
    assert at["jumps_before_stuck"] == 2
    after = rules_outcome(_run(stuck_from=401), P)
    assert after["jumps_before_stuck"] == 3


def test_a_somersault_is_not_lying_overturned():
    run = _run()
    n = round(STUCK_S / lm.CONTROL_DT)
    run.obs[100 : 100 + n - 1, 8] = -1.0  # one step short
    assert rules_outcome(run, P)["stuck_overturned_s"] is None
    run.obs[100 + n - 1, 8] = -1.0
    assert rules_outcome(run, P)["stuck_overturned_s"] == 100 * lm.CONTROL_DT


def test_the_head_of_a_run_is_a_shorter_run():
    run = _run()
    run = RulesRun(run.qpos, run.obs, run.ctrl, run.jumps, 0.3, True, Debris())
    h = run.head(50, P)
    assert len(h.qpos) == len(h.obs) == len(h.ctrl) == 51
    np.testing.assert_array_equal(h.qpos, run.qpos[:51])
    np.testing.assert_array_equal(h.obs, run.obs[:51])
    np.testing.assert_array_equal(h.ctrl, run.ctrl[:51])
    assert (h.change_time, h.unstable, h.scene) == (0.3, True, Debris())
    assert h.jumps == []  # found again: a level body never jumps


@dataclass(frozen=True)
class Raised(Flat):
    """Ground 6 cm up everywhere (heights only: never simulated)."""

    name: ClassVar[str] = "raised"

    @property
    def is_flat(self):
        return False

    def heights(self, x, y, body_length):
        return np.full(np.broadcast(x, y).shape, 0.06)


def test_the_head_of_a_run_finds_its_jumps_above_its_own_ground():
    run = _run(jumps=())
    stand = lm.standing_height(P) + JUMP_THRESHOLD_BL * P.body_length
    run.qpos[:, 2] = lm.standing_height(P)
    run.qpos[10:30, 2] = stand + 0.05  # 5 cm above the jump threshold
    flat = run.head(50, P)
    assert [(j.start, j.end) for j in flat.jumps] == [(10, 30)]
    raised = RulesRun(run.qpos, run.obs, run.ctrl, [], 0.3, False, Raised())
    assert raised.head(50, P).jumps == []  # 1 cm below it over that ground
