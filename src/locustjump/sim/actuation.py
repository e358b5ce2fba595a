"""The paper's actuation rule, for a whole batch: each of the 4 network
outputs is a change of a servo's target angle in [-10, +10] deg per control
step (paper §3; SPEC "Controller"); targets are clipped to the joint range.
The compiled form is :func:`locustjump.sim.kernels.actuate`."""

from __future__ import annotations

import numpy as np

# defined beside the compiled kernels, whose cached code bakes it in
from locustjump.sim.kernels import MAX_DELTA as MAX_DELTA

N_ACTUATORS = 4


def apply_deltas(
    targets: np.ndarray,
    deltas: np.ndarray,
    ranges: np.ndarray,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """New servo targets: ``clip(targets + clip(deltas, +-10 deg), range)``.

    Args:
      targets: (n, 4) current targets, radians.
      deltas: (n, 4) requested changes, radians (clipped to +-10 deg).
      ranges: (4, 2) joint ranges, radians.
      out: where to write the result; may be ``targets`` itself.

    Returns:
      (n, 4) new targets.
    """
    step = np.maximum(deltas, -MAX_DELTA)
    np.minimum(step, MAX_DELTA, out=step)
    step += targets
    np.maximum(step, ranges[:, 0], out=step)
    new: np.ndarray = np.minimum(step, ranges[:, 1], out=step if out is None else out)
    return new
