"""The compiled control callback of the in-callback engine
(:mod:`~locustjump.sim.engine.incallback`, strategy ``numba``): MuJoCo's
``mjcb_control``, the context array it reads, and its installation.

Per simulation, the callback of every substep (MuJoCo calls it in
``mj_forward``, after the position and velocity stages, before the actuator
forces) keeps the maximum of the touch sensors; at the first substep of a
control step it computes the 9 inputs of the state the previous control step
left, records them, runs the episode's network and writes the new servo
targets into that simulation's ``ctrl``, with :mod:`~locustjump.sim.kernels`
on one episode's slices: the numbers of the step-by-step compiled loop
(:func:`~.compiled.run_compiled`), bit for bit (tested). MuJoCo computes the
touch sensors after the callback, so a substep's callback sees the substep
before's: a control step's maximum is complete at the next one's first
callback, where it is used.

The callback finds its data through the simulation's ``userdata`` (the model
has ``nuserdata = 3``: a marker, the address of the rollout's context, the
episode's index); every other simulation in the process (no marker) is left
alone. The offsets of the few ``mjData``/``mjModel`` fields it reads are
literals here, checked at import against those :mod:`locustjump.sim.engine.mjlayout`
computes for the running MuJoCo; where they differ, this path is unavailable
(:data:`AVAILABLE`) and the step-by-step loop runs instead.
"""

from __future__ import annotations

import hashlib
import logging
import threading
from collections.abc import Callable
from typing import Any, cast

import mujoco
import numpy as np
from mujoco.batch import Batch
from numba import carray, cfunc, njit, types
from numba.extending import intrinsic
from numpy.typing import NDArray

from locustjump.sim import kernels as K
from locustjump.sim import model as lm
from locustjump.sim.controller import KernelSpec
from locustjump.sim.engine import mjlayout
from locustjump.sim.engine.compiled import CompiledStep
from locustjump.sim.engine.job import STEP_RECORDS, RolloutJob

#: userdata[0] of a simulation this path drives
USERDATA_MARK = 20061110.0
NUSERDATA = 3

#: Offsets of mjData's qpos, ctrl, sensordata, userdata and warning and of
#: mjModel's nuserdata in MuJoCo 4.0 (64-bit). Literals, so that the cached
#: compiled callback and this source agree; checked against the running
#: MuJoCo at import, and this path is off where they differ.
OFFSETS = (160688, 160744, 160816, 160808, 160264, 736)
_OFF_QPOS, _OFF_CTRL, _OFF_SENS, _OFF_USER, _OFF_WARN, _OFF_NUSER = OFFSETS
#: SHA-256 of the kernels' sources (``kernels.SOURCES``: kernels.py and
#: cephes.py), whose functions the cached compiled code below calls: Numba's
#: cache notices changes to this file only, so a change there must change this
#: line too (``tests/test_incallback.py`` says so, with the digest)
KERNELS_SHA256 = "24b248d00d673cef785a8996a8944d932e8785c474a57d783f4f2eb753b642cd"


def kernels_digest(sources: tuple[str, ...] = K.SOURCES) -> str:
    """SHA-256 of the files ``sources``, one after the other."""
    digest = hashlib.sha256()
    for path in sources:
        with open(path, "rb") as f:
            digest.update(f.read())
    return digest.hexdigest()


_LAYOUT = mjlayout.offsets(NUSERDATA) == OFFSETS
AVAILABLE = _LAYOUT and kernels_digest() == KERNELS_SHA256
if not AVAILABLE:
    why = (
        f"MuJoCo {mujoco.__version__}'s mjData layout is not the one the "
        "in-callback engine was built for"
        if not _LAYOUT
        else "kernels.py or cephes.py changed since callback.py was compiled "
        "against them (KERNELS_SHA256)"
    )
    why += "; the step-by-step compiled loop runs instead (same results, slower)"
    # nothing a caller can change: a diagnostic (logging), not a warning to
    # act on (warnings.warn)
    logging.getLogger(__name__).warning(why)
_NWARNING = int(mujoco.mjtWarning.mjNWARNING)


def _address_of(typingctx: Any, ptr: Any) -> Any:
    """The address of a raw pointer, as an int64."""
    if not isinstance(ptr, types.RawPointer):
        return None

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.ptrtoint(args[0], context.get_value_type(types.int64))

    return types.int64(ptr), codegen


def _pointer_to(typingctx: Any, addr: Any) -> Any:
    """An int64 address as a void pointer."""
    if not isinstance(addr, types.Integer):
        return None

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], context.get_value_type(types.voidptr))

    return types.voidptr(addr), codegen


# Compiled code calls an intrinsic without its typing context, the argument
# Numba's stubs count first: the casts give the calls' own types
_address = cast("Callable[[Any], int]", intrinsic(_address_of))
_pointer = cast("Callable[[Int], Any]", intrinsic(_pointer_to))


# --- the rollout's context: one int64 array of sizes and addresses ---------------

# sizes
(_KIND, _N, _T, _S, _NQ, _NS, _NU, _NMEM, _NTOUCH, _H, _C, _OUTPUT, _EVERY,
 _SHARED) = range(14)  # fmt: skip
# addresses
(_BL, _COUNTER, _TMAX, _JOINTS, _TOUCH, _LO, _HI, _OBS, _DELTAS, _HIDDEN, _CHOICE,
 _MEMORY, _RQ, _RO, _RC, _RM) = range(14, 30)  # fmt: skip
#: the network's (mlp) or the switcher's w1 b1 w2 b2, then the switched nets',
#: each (n, ...) per episode: address, then 5 dims
_NET, _NET_ARRAYS = 30, 8
_LEN = _NET + 6 * _NET_ARRAYS
_MLP, _SWITCH = 1, 2
#: the context's type; its sizes and addresses, as compiled code reads them
Ctx = NDArray[np.int64]
Int = int | np.int64


@njit(inline="always")
def _f64(addr: Int, shape: Any) -> K.F64:
    return carray(_pointer(addr), shape, np.float64)


@njit(inline="always")
def _i64(addr: Int, shape: Any) -> Ctx:
    return carray(_pointer(addr), shape, np.int64)


@njit(inline="always")
def _net3(ctx: Ctx, k: int, e: Int) -> K.F64:
    """Net array ``k`` of the context, episode ``e``'s (2-D) slice."""
    a = _NET + 6 * k
    net: K.F64 = _f64(ctx[a], (ctx[a + 1], ctx[a + 2], ctx[a + 3]))[e]
    return net


@njit(inline="always")
def _net4(ctx: Ctx, k: int, e: Int) -> K.F64:
    a = _NET + 6 * k
    net: K.F64 = _f64(ctx[a], (ctx[a + 1], ctx[a + 2], ctx[a + 3], ctx[a + 4]))[e]
    return net


@njit(inline="always")
def _net5(ctx: Ctx, k: int, e: Int) -> K.F64:
    a = _NET + 6 * k
    shape = (ctx[a + 1], ctx[a + 2], ctx[a + 3], ctx[a + 4], ctx[a + 5])
    net: K.F64 = _f64(ctx[a], shape)[e]
    return net


@njit(inline="always")
def _records(addr: Int, n: Int, T: Int, k: Int, e: Int) -> K.F64:
    if addr == 0:
        return np.empty((0, 0, 0))
    return _f64(addr, (n, T + 1, k))[e : e + 1]


@njit(cache=True, error_model="numpy")
def _episode(ctx: Ctx, e: Int, t: int, qpos: K.F64, ctrl: K.F64) -> None:
    """Control step ``t`` of episode ``e``: observe the state the previous
    control step left, record row ``t``, run the network, actuate."""
    n, T, nq, nu, nmem = ctx[_N], ctx[_T], ctx[_NQ], ctx[_NU], ctx[_NMEM]
    tmax = _f64(ctx[_TMAX], (n, ctx[_NS]))[e : e + 1]
    obs = _f64(ctx[_OBS], (n, 9, 1))[e]
    deltas = _f64(ctx[_DELTAS], (n, 4, 1))[e]
    hidden = _f64(ctx[_HIDDEN], (n, ctx[_H], 1))[e]
    memory = _f64(ctx[_MEMORY], (n, nmem))[e : e + 1]
    K.observe(qpos, tmax, _i64(ctx[_JOINTS], 4), _i64(ctx[_TOUCH], ctx[_NTOUCH]),
              _f64(ctx[_BL], 1)[0], obs)  # fmt: skip
    never = np.zeros(1, np.bool_)
    K.record(t, qpos, obs, ctrl, memory, _records(ctx[_RQ], n, T, nq, e),
             _records(ctx[_RO], n, T, 9, e), _records(ctx[_RC], n, T, nu, e),
             _records(ctx[_RM], n, T, nmem, e), never, False)  # fmt: skip
    if ctx[_KIND] == _MLP:
        K.mlp(_net4(ctx, 0, e), _net3(ctx, 1, e), _net4(ctx, 2, e), _net3(ctx, 3, e),
              obs, deltas, hidden, ctx[_OUTPUT])  # fmt: skip
    else:
        if t % ctx[_EVERY] == 0:  # the switcher picks (kernels.switch's rule)
            choice = _f64(ctx[_CHOICE], (n, ctx[_C], 1))[e]
            K.mlp(_net4(ctx, 0, e), _net3(ctx, 1, e), _net4(ctx, 2, e),
                  _net3(ctx, 3, e), obs, choice, hidden, K.SIGMOID)  # fmt: skip
            best = 0
            for c in range(1, choice.shape[0]):
                if choice[c, 0] > choice[best, 0]:
                    best = c
            memory[0, 0] = best
        # only the picked network: its numbers are those kernels.switch selects
        c, s = int(memory[0, 0]), 0 if ctx[_SHARED] else e
        K.mlp(_net5(ctx, 4, s)[c], _net4(ctx, 5, s)[c], _net5(ctx, 6, s)[c],
              _net4(ctx, 7, s)[c], obs, deltas, hidden, K.DELTA)  # fmt: skip
    K.actuate(ctrl, deltas, _f64(ctx[_LO], nu), _f64(ctx[_HI], nu), never, False)


@njit(inline="always")
def _field(base: int, offset: int) -> int:
    """The int64 (a pointer or an mjtSize) at ``base + offset``."""
    value: int = _i64(base + offset, 1)[0]
    return value


@cfunc(types.void(types.voidptr, types.voidptr), cache=True, error_model="numpy")
def _control(m: Any, d: Any) -> None:
    """``mjcb_control``: a substep of one simulation (see the module's doc)."""
    if _field(_address(m), _OFF_NUSER) < NUSERDATA:
        return
    base = _address(d)
    user = _f64(_field(base, _OFF_USER), NUSERDATA)
    if user[0] != USERDATA_MARK:
        return
    warning = carray(_pointer(base + _OFF_WARN), 2 * _NWARNING, np.int32)
    for w in range(_NWARNING):
        if warning[2 * w + 1] > 0:  # MuJoCo reset it: the episode has failed
            return
    ctx = _i64(np.int64(user[1]), _LEN)
    e = np.int64(user[2])
    n, S, ns = ctx[_N], ctx[_S], ctx[_NS]
    counter = _i64(ctx[_COUNTER], n)
    j = counter[e]
    counter[e] = j + 1
    if j == 0:  # the start state: its inputs and action came from Python
        return
    tmax = _f64(ctx[_TMAX], (n, ns))
    sens = _f64(_field(base, _OFF_SENS), ns)  # computed by the substep before
    if (j - 1) % S == 0:
        for c in range(ns):
            tmax[e, c] = sens[c]
    else:
        for c in range(ns):
            tmax[e, c] = max(tmax[e, c], sens[c])
    if j % S == 0:
        qpos = _f64(_field(base, _OFF_QPOS), (1, ctx[_NQ]))
        ctrl = _f64(_field(base, _OFF_CTRL), (1, ctx[_NU]))
        _episode(ctx, e, j // S, qpos, ctrl)


# --- a rollout's context written, the callback installed -------------------------


def context(
    batch: Batch,
    job: RolloutJob,
    step: CompiledStep,
    rec: dict[str, np.ndarray],
    spec: KernelSpec,
) -> tuple[Ctx, K.F64, object]:
    """The context array the callback reads, the touch maxima it keeps, and
    every array it points into (which must outlive the rollout), for the
    controller's compiled form ``spec``."""
    m, ctl, n = batch.model, job.controller, job.n_episodes
    idx = lm.ModelIndex.of(m)
    nets = spec[1] + (spec[2] if spec[0] == "switch" else ())
    per_episode = [np.ascontiguousarray(np.moveaxis(a, -1, 0)[..., None]) for a in nets]
    # the switched networks, when every episode holds the same: one copy
    shared = all((a == a[:1]).all() for a in per_episode[4:])
    if shared:
        per_episode[4:] = [a[:1].copy() for a in per_episode[4:]]
    if spec[0] == "mlp":
        kind, hidden, choice, output, every = _MLP, nets[0].shape[0], 1, spec[2], 1
    else:
        kind, hidden = _SWITCH, max(nets[0].shape[0], nets[4].shape[1])
        choice, output, every = nets[2].shape[0], K.SIGMOID, spec[3]
    tmax = np.zeros((n, m.nsensordata))
    arrays = [np.array([job.model_params.body_length]), np.zeros(n, np.int64), tmax,
              np.asarray(idx.qpos_joints, np.int64), np.asarray(idx.touch, np.int64),
              step.lo, step.hi, np.zeros((n, 9, 1)), np.zeros((n, 4, 1)),
              np.zeros((n, hidden, 1)), np.zeros((n, choice, 1)),
              step.memory, *(rec.get(k) for k in STEP_RECORDS)]  # fmt: skip
    ctx = np.zeros(_LEN, np.int64)
    ctx[:_BL] = (kind, n, job.n_steps, job.model_params.substeps, m.nq,
                 m.nsensordata, m.nu, ctl.memory_size, len(idx.touch), hidden, choice,
                 output, every, shared)  # fmt: skip
    for i, a in enumerate(arrays):
        if a is not None:
            assert a.flags.c_contiguous
            ctx[_BL + i] = a.ctypes.data
    for k, a in enumerate(per_episode):
        ctx[_NET + 6 * k] = a.ctypes.data
        ctx[_NET + 6 * k + 1 : _NET + 6 * k + 1 + a.ndim] = a.shape
    return ctx, tmax, (arrays, per_episode)


_LOCK = threading.Lock()
_users = 0  # rollouts running with the callback installed


class installed:
    """``mjcb_control`` set to this path's callback while any rollout of this
    process runs on it (``as ok``: False, and nothing changed, when another
    callback is installed)."""

    def __enter__(self) -> bool:
        global _users
        with _LOCK:
            if _users == 0:
                if mujoco.get_mjcb_control() is not None:
                    self.ok = False
                    return False
                mujoco.set_mjcb_control(_control.ctypes)
            _users += 1
        self.ok = True
        return True

    def __exit__(self, *exc: object) -> None:
        global _users
        if not self.ok:
            return
        with _LOCK:
            _users -= 1
            if _users == 0:
                mujoco.set_mjcb_control(None)
