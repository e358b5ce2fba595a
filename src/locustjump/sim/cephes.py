"""``exp`` and ``tanh`` for the compiled kernels (:mod:`locustjump.sim.kernels`):
Cephes' algorithms (``exp.c``, ``tanh.c``) as plain arithmetic.

NumPy's ``np.exp`` and ``np.tanh`` are NumPy's own SIMD routines, and a
library's ``exp`` depends on the machine it runs on; these are rational
approximations in IEEE operations alone, both branches of a choice computed
and one selected, so that the compiler vectorizes a loop over episodes that
calls them and the result depends on no library. They are within two units in
the last place of NumPy's (``tests/test_engine.py``).

The kernels compile these functions into their own machine code, which
Numba caches keyed on ``kernels.py`` alone: ``kernels.py`` carries this
file's SHA-256 (``CEPHES_SHA256``), so a change here must change it too. Like
the kernels, nothing here reads a value from another locustjump module.
"""

from __future__ import annotations

import numpy as np
from numba import njit

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
