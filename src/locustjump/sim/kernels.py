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
approximations in plain arithmetic (so that the compiler vectorizes them over
episodes and the result depends on no library): within a few units in the
last place of NumPy's (tested). Each path is deterministic and independent of
threads and batch splits; a run's ``config.toml`` records its path.

Weights are laid out episode-last ("structure of arrays"), so that every loop's
innermost index runs over episodes and vectorizes.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

# Numba caches the machine code of these kernels keyed on this file alone, and
# a global a kernel reads is frozen into that code: so every value a kernel
# reads is defined here, never imported (tests/test_incallback.py checks it).
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

# Cephes exp.c: exp(x) = 2^n exp(r), r in [-ln2/2, ln2/2], a (3,4) Pade form
_LOG2E = 1.4426950408889634073599
_C1 = 6.93145751953125e-1
_C2 = 1.42860682030941723212e-6
_EP0, _EP1, _EP2 = 1.26177193074810590878e-4, 3.02994407707441961300e-2, 1.0
_EQ0, _EQ1 = 3.00198505138664455042e-6, 2.52448340349684104192e-3
_EQ2, _EQ3 = 2.27265548208155028766e-1, 2.0
_EXP_LO, _EXP_HI = -700.0, 700.0  # clamp (exp(-700) ~ 1e-304: still normal)
#: 2^n for n in [-1010, 1010] (a table: a bit cast would not vectorize)
_POW2 = np.ldexp(1.0, np.arange(-1010, 1011))
_POW2_BIAS = 1010
# Cephes tanh.c: |x| < 0.625: x + x^3 P(x^2)/Q(x^2); else 1 - 2/(exp(2|x|)+1)
_TP0 = -9.64399179425052238628e-1
_TP1 = -9.92877231001918586564e1
_TP2 = -1.61468768441708447952e3
_TQ0 = 1.12811678491632931402e2
_TQ1 = 2.23548839060100448583e3
_TQ2 = 4.84406305325125486048e3


@njit(cache=True, inline="always", error_model="numpy")
def _exp_parts(x: float) -> tuple[float, float]:
    """``(n, m)`` with e^x = m * 2^n: Cephes' reduction to r in [-ln2/2,
    ln2/2] and its (3,4) Pade form of e^r."""
    px = np.floor(_LOG2E * x + 0.5)
    r = x - px * _C1
    r = r - px * _C2
    rr = r * r
    p = r * ((_EP0 * rr + _EP1) * rr + _EP2)
    q = ((_EQ0 * rr + _EQ1) * rr + _EQ2) * rr + _EQ3
    return px, 1.0 + 2.0 * (p / (q - p))


@njit(cache=True, inline="always", error_model="numpy")
def exp(x: float) -> float:
    """e^x (x clamped to [-700, 700]), Cephes' algorithm, branch-free."""
    px, y = _exp_parts(min(max(x, _EXP_LO), _EXP_HI))
    e: float = y * _POW2[int(px) + _POW2_BIAS]
    return e


@njit(cache=True, inline="always", error_model="numpy")
def _exp_tanh(x: float) -> float:
    """e^x for x in [0, 40] (tanh's range), as :func:`exp` but with 2^n made
    by exact multiplications and selects instead of a table (vectorizes)."""
    px, y = _exp_parts(x)
    # 2^px, px in [0, 58], bit by bit (unrolled: selects of exact products)
    t = px >= 32.0
    px, y = (px - 32.0, y * 4294967296.0) if t else (px, y)
    t = px >= 16.0
    px, y = (px - 16.0, y * 65536.0) if t else (px, y)
    t = px >= 8.0
    px, y = (px - 8.0, y * 256.0) if t else (px, y)
    t = px >= 4.0
    px, y = (px - 4.0, y * 16.0) if t else (px, y)
    t = px >= 2.0
    px, y = (px - 2.0, y * 4.0) if t else (px, y)
    return y * 2.0 if px >= 1.0 else y


@njit(cache=True, inline="always", error_model="numpy")
def tanh(x: float) -> float:
    """tanh(x), Cephes' algorithm; both branches computed, one selected (so
    that a loop over episodes vectorizes)."""
    z = abs(x)
    s = x * x
    ratio = ((_TP0 * s + _TP1) * s + _TP2) / (((s + _TQ0) * s + _TQ1) * s + _TQ2)
    small = x + x * s * ratio
    big = 1.0 - 2.0 / (_exp_tanh(min(z, 20.0) * 2.0) + 1.0)
    big = -big if x < 0.0 else big
    return small if z < 0.625 else big


@njit(cache=True, inline="always", error_model="numpy")
def _layer_sum(w: F64, k: int, x: F64, out: F64) -> None:
    """``out[k, e] = sum_j w[k, j, e] * x[j, e]``, summed in input order."""
    for e in range(x.shape[1]):
        out[k, e] = w[k, 0, e] * x[0, e]
    for j in range(1, x.shape[0]):
        for e in range(x.shape[1]):
            out[k, e] += w[k, j, e] * x[j, e]


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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
