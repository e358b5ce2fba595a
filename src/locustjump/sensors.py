"""The paper's 9 network inputs and its actuation rule, for a whole batch.

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

* I1–I4: joint zeros are chosen in :mod:`locustjump.model` so that every range
  lies inside (0, 2 pi): the raw hinge angle is the input, it never wraps.
* I5: "on" when either hind tarsus's touch sensor reads a positive normal force.
  The touch value comes from the forward pass of the last physics substep (as
  ``mj_step`` leaves ``sensordata``), i.e. at most one substep old.
* I6: H is the height of the body centre above the floor **in body lengths**
  (nose to tail), so I6 is scale-free: ~0.86 standing, ~0.3 at a 2-body-length
  apex. In metres it would be almost constant at real scale.
* I7–I9: "inner product of the local axis and the world axis" read as the world
  up-axis expressed in the body frame: the third row of the body's rotation
  matrix. I9 is the body's up-axis U_z (1 upright, -1 on its back), I7 the
  pitch (nose up > 0), I8 the roll.

Actuation: each output is a change of a servo's target angle in [-10, +10] deg
per control step; targets are clipped to the joint range.
"""

from __future__ import annotations

import numpy as np

N_INPUTS = 9
N_ACTUATORS = 4
MAX_DELTA = np.radians(10.0)  # (rad) largest target change per control step


def up_axis_in_body(quat: np.ndarray) -> np.ndarray:
    """World z expressed in the body frame, (n, 3), from quaternions (n, 4) wxyz.

    Equal to the third row of the rotation matrix: (x_b . z, y_b . z, z_b . z).
    """
    w, x, y, z = quat[:, 0], quat[:, 1], quat[:, 2], quat[:, 3]
    out = np.empty((quat.shape[0], 3))
    np.multiply(x, z, out=out[:, 0])
    out[:, 0] -= w * y
    out[:, 0] *= 2.0
    np.multiply(y, z, out=out[:, 1])
    out[:, 1] += w * x
    out[:, 1] *= 2.0
    out[:, 2] = 1.0 - 2.0 * (x * x + y * y)
    return out


def paper_inputs(
    qpos: np.ndarray,
    sensordata: np.ndarray,
    *,
    joint_adr: np.ndarray,
    touch_adr: np.ndarray,
    body_length: float,
) -> np.ndarray:
    """The 9 inputs I1–I9 for a batch.

    Args:
      qpos: (n, nq) positions; the free joint's position and quaternion come
        first (qpos[:, 0:7]).
      sensordata: (n, nsensordata).
      joint_adr: (4,) qpos addresses of the actuated joints, order I1–I4.
      touch_adr: (2,) sensordata addresses of the two tarsus touch sensors.
      body_length: (m) body length, the unit of H in I6.

    Returns:
      (n, 9) float64 inputs.
    """
    n = qpos.shape[0]
    obs = np.empty((n, N_INPUTS))
    obs[:, 0:4] = qpos[:, joint_adr]
    touching = (sensordata[:, touch_adr] > 0.0).any(axis=1)
    obs[:, 4] = np.where(touching, -1.0, 1.0)
    height = np.maximum(qpos[:, 2], 0.0) / body_length
    obs[:, 5] = 1.0 / (height + 1.0)
    obs[:, 6:9] = up_axis_in_body(qpos[:, 3:7])
    return obs


def apply_deltas(
    targets: np.ndarray, deltas: np.ndarray, ranges: np.ndarray
) -> np.ndarray:
    """New servo targets: ``clip(targets + clip(deltas, +-10 deg), range)``.

    Args:
      targets: (n, 4) current targets, radians.
      deltas: (n, 4) requested changes, radians (clipped to +-10 deg).
      ranges: (4, 2) joint ranges, radians.

    Returns:
      (n, 4) new targets.
    """
    step = np.clip(deltas, -MAX_DELTA, MAX_DELTA)
    return np.clip(targets + step, ranges[:, 0], ranges[:, 1])
