"""Compiled per-control-step work of the rollout engine's ``numba`` path.

Between two ``Batch.rollout`` calls the engine reduces the touch sensors over
the substeps, checks for blow-ups, computes the 9 inputs, records the step,
evaluates every network and applies the actuation rule. The ``numpy`` strategy
(:class:`locustjump.sim.engine.numpy_step.NumpyStep`) does that in about 20
NumPy calls, ~100 µs per control step whatever the batch size; here it is one
call of a compiled kernel over the whole batch (:func:`step_mlp`,
:func:`step_switch`), its arrays passed as named structures (:class:`Rollout`,
:class:`MLPAct`, :class:`SwitchAct`).

Arithmetic. Sensors, the actuation rule, the touch reduction and the checks
are the same IEEE operations in the same order as in NumPy, so they agree bit
for bit. The networks do not: NumPy's ``matmul`` sums through BLAS (whose order
depends on the CPU's kernel) and ``np.tanh`` is NumPy's own SIMD routine. Here
the sums run in input order, and ``tanh``/``exp`` are Cephes' rational
approximations in plain arithmetic (:mod:`locustjump.sim.cephes`: the
compiler vectorizes them over episodes and the result depends on no
library): within a few units in the last place of NumPy's (tested). Each
path is deterministic and independent of threads and batch splits; a run's
``config.toml`` records its path.

Weights are laid out episode-last ("structure of arrays"), so that every loop's
innermost index runs over episodes and vectorizes.
"""

from __future__ import annotations

import hashlib
import logging
import math
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

from locustjump.sim import cephes
from locustjump.sim.cephes import exp as exp
from locustjump.sim.cephes import tanh as tanh

# Numba caches a kernel's machine code keyed on this file alone, with what it
# calls and every global it reads compiled in: so a value a kernel reads is
# defined here, never imported, but for cephes.py's functions (checked by
# tests/test_incallback.py), whose SHA-256 this line carries: a change there
# must change this file too. Until it does, the kernels compile afresh in
# every process rather than read a cache that may hold the old cephes.py.
CEPHES_SHA256 = "fc4ff28fe6d7cc1366844ab25259330f5ba3eb2589471291b2ab8073a3df8d3b"
#: the files the kernels' machine code comes from (the in-callback engine,
#: whose cached callback calls the kernels, hashes them all)
SOURCES = (__file__, cephes.__file__)


def _sha256(path: str) -> str:
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


#: whether the kernels are cached (cephes.py is the file this one names)
CACHE = _sha256(cephes.__file__) == CEPHES_SHA256
if not CACHE:  # a diagnostic, as the in-callback engine's fallback
    logging.getLogger(__name__).warning(
        "cephes.py changed since kernels.py named it (CEPHES_SHA256): the "
        "kernels are compiled afresh in every process (same results, slower start)"
    )
# actuation.py takes the rule's limit from here.
MAX_DELTA = np.radians(10.0)  # (rad) largest target change per control step

#: the kernels' array types (annotations only: Numba types a kernel from its
#: arguments): float64, index (intp) and flag arrays; one network's ``w1, b1,
#: w2, b2``, episode-last
F64 = NDArray[np.float64]
Index = NDArray[np.intp]
Flags = NDArray[np.bool_]
Net = tuple[F64, ...]

# output squashing codes (MLP.output)
DELTA, SIGMOID, LINEAR = 0, 1, 2
OUTPUTS = {"delta": DELTA, "sigmoid": SIGMOID, "linear": LINEAR}


@njit(cache=CACHE, inline="always", error_model="numpy")
def _layer_sum(w: F64, k: int, x: F64, out: F64) -> None:
    """``out[k, e] = sum_j w[k, j, e] * x[j, e]``, summed in input order."""
    for e in range(x.shape[1]):
        out[k, e] = w[k, 0, e] * x[0, e]
    for j in range(1, x.shape[0]):
        for e in range(x.shape[1]):
            out[k, e] += w[k, j, e] * x[j, e]


@njit(cache=CACHE, error_model="numpy")
def mlp(
    w1: F64, b1: F64, w2: F64, b2: F64, x: F64, out: F64, hidden: F64, output: int
) -> None:
    """One network per episode, episode-last: ``w1 (h, i, n)``, ``b1 (h, n)``,
    ``w2 (o, h, n)``, ``b2 (o, n)``, inputs ``x (i, n)``; writes ``out (o, n)``
    (``hidden (h, n)`` is scratch)."""
    h, n = w1.shape[0], x.shape[1]
    for k in range(h):
        _layer_sum(w1, k, x, hidden)
        for e in range(n):
            hidden[k, e] = tanh(hidden[k, e] + b1[k, e])
    for k in range(w2.shape[0]):
        _layer_sum(w2, k, hidden[:h], out)
        if output == DELTA:
            for e in range(n):
                out[k, e] = tanh(out[k, e] + b2[k, e]) * MAX_DELTA
        elif output == SIGMOID:
            for e in range(n):
                out[k, e] = 1.0 / (1.0 + exp(-(out[k, e] + b2[k, e])))
        else:
            for e in range(n):
                out[k, e] += b2[k, e]


@njit(cache=CACHE, error_model="numpy")
def switch(
    t: int,
    every: int,
    sw: Net,
    nets: Net,
    memory: F64,
    x: F64,
    out: F64,
    choice: F64,
    scratch: F64,
    hidden: F64,
) -> None:
    """The composed switcher: every ``every`` steps the switcher network ``sw``
    (sigmoid outputs) picks, per episode, the simple network with the largest
    output (the first on ties, as ``np.argmax``) into ``memory[:, 0]``; each
    episode then runs its picked network of ``nets`` (delta outputs)."""
    n = x.shape[1]
    if t % every == 0:
        w1, b1, w2, b2 = sw
        mlp(w1, b1, w2, b2, x, choice, hidden, SIGMOID)
        for e in range(n):
            best = 0
            for c in range(1, choice.shape[0]):
                if choice[c, e] > choice[best, e]:
                    best = c
            memory[e, 0] = best
    w1s, b1s, w2s, b2s = nets
    for c in range(w1s.shape[0]):
        mlp(w1s[c], b1s[c], w2s[c], b2s[c], x, scratch, hidden, DELTA)
        for e in range(n):
            if memory[e, 0] == c:
                for k in range(out.shape[0]):
                    out[k, e] = scratch[k, e]


@njit(cache=CACHE, error_model="numpy")
def sense_and_check(
    sub: F64,
    ids: Index,
    sens: F64,
    qpos: F64,
    warning: NDArray[np.int32],
    unstable: Flags,
    newly: Flags,
) -> int:
    """Per-substep sensordata ``sub (len(ids), substeps, ns)`` of simulations
    ``ids`` reduced to their maximum into ``sens``; flags in ``newly`` the
    episodes not yet ``unstable`` whose warning counters (``warning (n,
    mjNWARNING, 2)``, the count is ``[..., 1]``) rose or whose ``qpos`` is not
    finite, and returns how many: the engine's one rule
    (:func:`locustjump.sim.engine.job.went_unstable`), compiled."""
    for i in range(ids.shape[0]):
        e = ids[i]
        for c in range(sub.shape[2]):
            m = sub[i, 0, c]
            for s in range(1, sub.shape[1]):
                m = max(m, sub[i, s, c])
            sens[e, c] = m
    count = 0
    for e in range(qpos.shape[0]):
        bad = False
        for w in range(warning.shape[1]):
            bad |= warning[e, w, 1] > 0
        for j in range(qpos.shape[1]):
            bad |= not math.isfinite(qpos[e, j])
        newly[e] = bad and not unstable[e]
        count += newly[e]
    return count


@njit(cache=CACHE, error_model="numpy")
def observe(
    qpos: F64, sens: F64, joints: Index, touch: Index, body_length: float, obs: F64
) -> None:
    """The 9 paper inputs, episode-last ``obs (9, n)``: the arithmetic of
    :func:`locustjump.sim.sensors.paper_inputs`, operation for operation."""
    for e in range(qpos.shape[0]):
        for j in range(4):
            obs[j, e] = qpos[e, joints[j]]
        touching = 0.0
        for j in range(touch.shape[0]):
            if sens[e, touch[j]] > 0.0:
                touching = 1.0
        obs[4, e] = (1.0 - touching) - touching
        obs[5, e] = 1.0 / (max(qpos[e, 2], 0.0) / body_length + 1.0)
        w, x, y, z = qpos[e, 3], qpos[e, 4], qpos[e, 5], qpos[e, 6]
        obs[6, e] = (x * z - w * y) * 2.0
        obs[7, e] = (y * z + w * x) * 2.0
        obs[8, e] = 1.0 - (x * x + y * y) * 2.0


@njit(cache=CACHE, error_model="numpy")
def record(
    t: int,
    qpos: F64,
    obs: F64,
    ctrl: F64,
    memory: F64,
    rq: F64,
    ro: F64,
    rc: F64,
    rm: F64,
    stopped: Flags,
    any_stopped: bool,
) -> None:
    """Row ``t`` of the records ``rq, ro, rc, rm`` (an empty array: not
    recorded); episodes ``stopped`` repeat row ``t - 1``."""
    for e in range(qpos.shape[0]):
        src = t - 1 if any_stopped and stopped[e] else t
        if src == t:
            if rq.shape[0]:
                rq[e, t, :] = qpos[e, :]
            if ro.shape[0]:
                for j in range(obs.shape[0]):
                    ro[e, t, j] = obs[j, e]
            if rc.shape[0]:
                rc[e, t, :] = ctrl[e, :]
            if rm.shape[0]:
                rm[e, t, :] = memory[e, :]
        else:
            if rq.shape[0]:
                rq[e, t, :] = rq[e, src, :]
            if ro.shape[0]:
                ro[e, t, :] = ro[e, src, :]
            if rc.shape[0]:
                rc[e, t, :] = rc[e, src, :]
            if rm.shape[0]:
                rm[e, t, :] = rm[e, src, :]


@njit(cache=CACHE, error_model="numpy")
def actuate(
    ctrl: F64, deltas: F64, lo: F64, hi: F64, unstable: Flags, any_unstable: bool
) -> None:
    """``ctrl = clip(ctrl + clip(deltas, +-10 deg), range)`` for the episodes
    still running (the arithmetic of :func:`locustjump.sim.actuation.apply_deltas`);
    ``deltas`` is episode-last ``(4, n)``."""
    for e in range(ctrl.shape[0]):
        if any_unstable and unstable[e]:
            continue
        for k in range(ctrl.shape[1]):
            step = min(max(deltas[k, e], -MAX_DELTA), MAX_DELTA) + ctrl[e, k]
            ctrl[e, k] = min(max(step, lo[k]), hi[k])


def soa(a: np.ndarray) -> F64:
    """An (n, ...) per-episode array as a contiguous (..., n) one."""
    return np.ascontiguousarray(np.moveaxis(np.asarray(a, dtype=np.float64), 0, -1))


class Records(NamedTuple):
    """The records a rollout keeps, each ``(n, T + 1, ...)``; an empty
    ``(0, 0, 0)`` array for a field not recorded."""

    qpos: np.ndarray
    obs: np.ndarray
    ctrl: np.ndarray
    memory: np.ndarray


class Rollout(NamedTuple):
    """What every kernel call of one rollout reads and writes, over ``n``
    episodes: the batch's own ``qpos (n, nq)``, ``ctrl (n, nu)`` and
    ``warning (n, mjNWARNING, 2)``; the touch maxima ``sens (n, nsensordata)``;
    the flags ``unstable``/``newly (n,)``; the addresses ``joints (4,)`` and
    ``touch``; ``body_length`` (m); the inputs ``obs (9, n)``; the controller's
    ``memory (n, nmem)``; the records."""

    sens: np.ndarray
    qpos: np.ndarray
    warning: np.ndarray
    unstable: np.ndarray
    newly: np.ndarray
    joints: np.ndarray
    touch: np.ndarray
    body_length: float
    obs: np.ndarray
    ctrl: np.ndarray
    memory: np.ndarray
    records: Records


class MLPAct(NamedTuple):
    """One network per episode: ``net`` (w1, b1, w2, b2, episode-last), its
    ``output`` code, the outputs ``deltas (4, n)``, scratch ``hidden (h, n)``,
    the servo ranges ``lo``/``hi (nu,)``."""

    net: Net
    output: int
    deltas: np.ndarray
    hidden: np.ndarray
    lo: np.ndarray
    hi: np.ndarray


class SwitchAct(NamedTuple):
    """The composed switcher (:func:`switch`): ``every`` steps the switcher
    ``sw`` picks one of ``nets``; scratch ``choice (c, n)``, ``scratch (4, n)``,
    ``hidden (h, n)``; as :class:`MLPAct` otherwise."""

    every: int
    sw: Net
    nets: Net
    deltas: np.ndarray
    choice: np.ndarray
    scratch: np.ndarray
    hidden: np.ndarray
    lo: np.ndarray
    hi: np.ndarray


@njit(cache=CACHE, error_model="numpy")
def post_step(
    t: int, check: bool, sub: F64, ids: Index, stopped: bool, r: Rollout
) -> int:
    """After the physics of control step ``t - 1`` (``t == 0``: the start
    state, no ``sub``) of rollout ``r``: reduce the touch sensors of
    simulations ``ids`` and check (``check``; returns the number of newly
    failed episodes, and does nothing else, if any), then observe into
    ``r.obs`` and record row ``t`` (``stopped``: some episode failed, and
    those repeat their last row)."""
    if check:
        count = sense_and_check(sub, ids, r.sens, r.qpos, r.warning, r.unstable,
                                r.newly)  # fmt: skip
        if count:
            return count
    observe(r.qpos, r.sens, r.joints, r.touch, r.body_length, r.obs)
    rec = r.records
    record(t, r.qpos, r.obs, r.ctrl, r.memory, rec.qpos, rec.obs, rec.ctrl,
           rec.memory, r.unstable, stopped)  # fmt: skip
    return 0


@njit(cache=CACHE, error_model="numpy")
def step_mlp(
    t: int,
    check: bool,
    sub: F64,
    ids: Index,
    stopped: bool,
    act: bool,
    r: Rollout,
    a: MLPAct,
) -> int:
    """:func:`post_step`, then (``act``, when no episode newly failed) one
    network per episode and the actuation rule (``a``: :class:`MLPAct`):
    everything between two physics calls in one call."""
    count = post_step(t, check, sub, ids, stopped, r)
    if count == 0 and act:
        w1, b1, w2, b2 = a.net
        mlp(w1, b1, w2, b2, r.obs, a.deltas, a.hidden, a.output)
        actuate(r.ctrl, a.deltas, a.lo, a.hi, r.unstable, stopped)
    return count


@njit(cache=CACHE, error_model="numpy")
def step_switch(
    t: int,
    check: bool,
    sub: F64,
    ids: Index,
    stopped: bool,
    act: bool,
    r: Rollout,
    a: SwitchAct,
) -> int:
    """:func:`step_mlp` for the composed switcher (``a``: :class:`SwitchAct`)."""
    count = post_step(t, check, sub, ids, stopped, r)
    if count == 0 and act:
        switch(t, a.every, a.sw, a.nets, r.memory, r.obs, a.deltas, a.choice,
               a.scratch, a.hidden)  # fmt: skip
        actuate(r.ctrl, a.deltas, a.lo, a.hi, r.unstable, stopped)
    return count
