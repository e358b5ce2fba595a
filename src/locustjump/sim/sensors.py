"""The paper's 9 network inputs, for a whole batch (the outputs' actuation
rule: :mod:`locustjump.sim.actuation`).

Inputs (paper §3; SPEC "Controller"), computed from ``qpos`` and ``sensordata``:

=====  ==============================  ==========  ======  =========================
index  meaning                         range       unit    source element
=====  ==============================  ==========  ======  =========================
I1     left hip angle                  [0, 2 pi)   rad     joint ``hip_l``
I2     left knee angle                 [0, 2 pi)   rad     joint ``knee_l``
I3     right hip angle                 [0, 2 pi)   rad     joint ``hip_r``
I4     right knee angle                [0, 2 pi)   rad     joint ``knee_r``
I5     hind touch: +1 off, -1 on       {-1, +1}    -       sensors ``touch_l/r``
I6     1 / (H + 1)                     (0, 1]      -       joint ``root`` (z)
I7     body x-axis . world z           [-1, 1]     -       joint ``root`` (quat)
I8     body y-axis . world z           [-1, 1]     -       joint ``root`` (quat)
I9     body z-axis . world z           [-1, 1]     -       joint ``root`` (quat)
=====  ==============================  ==========  ======  =========================

Our readings (the paper's figures are lost):

* I1–I4: joint zeros are chosen in :mod:`locustjump.sim.model` so that every range
  lies inside (0, 2 pi): the raw hinge angle is the input, it never wraps.
* I5: "on" when either hind tarsus's touch sensor read a positive normal force
  at any physics substep of the last control step (the rollout engine passes
  the per-substep maximum of ``sensordata``; at the start state, the forward
  pass there). Sampling only the last substep made the rule-based kick depend
  on contact chatter: a tarsus that bounced off the floor for one substep at
  the sampling instant aborted the kick, so results changed with the substep
  count (``docs/physics.md``).
* I6: H is the height of the body centre above the floor **in body lengths**
  (nose to tail), so I6 is scale-free: ~0.86 standing, ~0.3 at a 2-body-length
  apex. In metres it would be almost constant at real scale.
* I7–I9: "inner product of the local axis and the world axis" read as the world
  up-axis expressed in the body frame: the third row of the body's rotation
  matrix. I9 is the body's up-axis U_z (1 upright, -1 on its back), I7 the
  pitch (nose up > 0), I8 the roll.
"""

from __future__ import annotations

import numpy as np

N_INPUTS = 9


def up_axis_in_body(quat: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """World z expressed in the body frame, (n, 3), from quaternions (n, 4) wxyz.

    Equal to the third row of the rotation matrix: (x_b . z, y_b . z, z_b . z).
    ``out``, if given, is an (n, 3) array (or view) to write into.
    """
    w, x, y, z = quat[:, 0], quat[:, 1], quat[:, 2], quat[:, 3]
    if out is None:
        out = np.empty((quat.shape[0], 3))
    tmp = w * y
    np.multiply(x, z, out=out[:, 0])
    out[:, 0] -= tmp
    out[:, 0] *= 2.0
    np.multiply(w, x, out=tmp)
    np.multiply(y, z, out=out[:, 1])
    out[:, 1] += tmp
    out[:, 1] *= 2.0
    np.multiply(x, x, out=tmp)
    tmp += y * y
    tmp *= 2.0
    np.subtract(1.0, tmp, out=out[:, 2])
    return out


def paper_inputs(
    qpos: np.ndarray,
    sensordata: np.ndarray,
    *,
    joint_adr: np.ndarray | slice,
    touch_adr: np.ndarray | slice,
    body_length: float,
) -> np.ndarray:
    """The 9 inputs I1–I9 for a batch.

    Args:
      qpos: (n, nq) positions; the free joint's position and quaternion come
        first (qpos[:, 0:7]).
      sensordata: (n, nsensordata).
      joint_adr: (4,) qpos addresses of the actuated joints, order I1–I4 (or
        the equivalent slice, which is faster).
      touch_adr: (2,) sensordata addresses of the two tarsus touch sensors (or
        a slice).
      body_length: (m) body length, the unit of H in I6.

    Returns:
      (n, 9) float64 inputs.
    """
    n = qpos.shape[0]
    obs = np.empty((n, N_INPUTS))
    obs[:, 0:4] = qpos[:, joint_adr]
    touching = (sensordata[:, touch_adr] > 0.0).any(axis=1)
    # +1 off the ground, -1 on it
    np.subtract(1.0, touching, out=obs[:, 4])
    obs[:, 4] -= touching
    height = obs[:, 5]
    np.maximum(qpos[:, 2], 0.0, out=height)
    height /= body_length
    height += 1.0
    np.divide(1.0, height, out=height)
    up_axis_in_body(qpos[:, 3:7], out=obs[:, 6:9])
    return obs
