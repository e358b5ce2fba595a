"""Behaviour metrics computed from recorded trajectories (pure functions)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from locustjump import model as lm

#: A jump is a stretch where the body centre is this many body lengths above
#: its standing height.
JUMP_THRESHOLD_BL = 0.1


@dataclass(frozen=True)
class Jump:
    start: int  # control step the body rose above the threshold
    apex_step: int
    end: int
    apex_height: float  # (m) body-centre height above the floor at the apex
    apex_x: float  # (m) x at the apex
    rise: float  # (m) apex height minus standing height


def find_jumps(qpos: np.ndarray, p: lm.LocustParams = lm.LocustParams()) -> list[Jump]:
    """Jumps of one trajectory ``qpos (T, nq)``: contiguous high stretches."""
    z = qpos[:, 2]
    stand = lm.standing_height(p)
    high = z > stand + JUMP_THRESHOLD_BL * p.body_length
    edges = np.diff(np.concatenate([[0], high.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    jumps = []
    for a, b in zip(starts, ends, strict=True):
        k = a + int(np.argmax(z[a:b]))
        jumps.append(
            Jump(int(a), k, int(b), float(z[k]), float(qpos[k, 0]), float(z[k] - stand))
        )
    return jumps
