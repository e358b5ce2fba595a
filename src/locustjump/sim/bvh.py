"""The world body's bounding volume hierarchy, rebuilt after compiling.

MuJoCo tests a creature body against a many-geom body (the debris scene's
world: boxes and walls) by walking both bodies' bounding volume hierarchies
(its midphase, ``mj_collideTree``); only geom pairs whose boxes overlap reach
the narrow phase. The compiler builds each tree by splitting a node at the
median geom centre along its longest side. On a debris field that puts the
long walls (15 m x 0.5 m at the default size) together with boxes in nodes
as large as the whole field, so that a creature body anywhere on it overlaps
them and the walk goes on down; every creature body pays it at every physics
step, touching nothing (``docs/performance.md``, "Debris at the floor's
cost").

:func:`rebuild_bvh` replaces a static body's tree by one split where the
surface area heuristic (the sum, over both halves, of a half's box surface
times its geom count) is least: same leaves, same leaf boxes, same number of
nodes, so MuJoCo walks it as its own. Only the walk changes: a leaf pair is
still tested on its geoms' own boxes, every node's box holds its leaves'
(rounded outwards), and MuJoCo sorts a body pair's contacts by geom after the
walk, so ``d.contact`` is the same, in content and order, at every step
(``tests/test_debris.py`` checks it against the compiler's tree).

MJCF cannot express a tree: a model file written by ``locustjump model``
loads with the compiler's, which simulates the same, a little slower.
"""

from __future__ import annotations

import mujoco
import numpy as np


def _surface(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    e = hi - lo
    area: np.ndarray = (
        e[..., 0] * e[..., 1] + e[..., 1] * e[..., 2] + e[..., 2] * e[..., 0]
    )
    return area


def _split(lo: np.ndarray, hi: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """A boolean mask of the leaves going left: the cheapest split (surface
    area heuristic) of the leaves sorted by centre along one of the axes
    (ties: geom id, then the lowest axis, then the leftmost split)."""
    n = len(ids)
    best: tuple[float, np.ndarray | None] = (np.inf, None)
    for axis in range(3):
        order = np.lexsort((ids, lo[:, axis] + hi[:, axis]))
        a_lo = np.minimum.accumulate(lo[order], axis=0)[:-1]
        a_hi = np.maximum.accumulate(hi[order], axis=0)[:-1]
        b_lo = np.minimum.accumulate(lo[order][::-1], axis=0)[::-1][1:]
        b_hi = np.maximum.accumulate(hi[order][::-1], axis=0)[::-1][1:]
        k = np.arange(1, n)
        cost = _surface(a_lo, a_hi) * k + _surface(b_lo, b_hi) * (n - k)
        i = int(np.argmin(cost))
        if cost[i] < best[0]:
            left = np.zeros(n, dtype=bool)
            left[order[: i + 1]] = True
            best = (cost[i], left)
    assert best[1] is not None  # two leaves or more: some split costs < inf
    return best[1]


def rebuild_bvh(m: mujoco.MjModel, body: int = 0) -> None:
    """Rebuild, in place, the tree of static ``body`` (default: the world) of
    compiled model ``m`` over the same leaves (nothing to do with fewer than
    three). Its nodes keep MuJoCo's layout: the root first, each node before
    its children (pre-order), child and geom ids per node, boxes as (centre,
    half-size) in the body's frame."""
    if m.body_dofnum[m.body_weldid[body]] != 0:
        raise ValueError(f"body {body} moves: only a static body's tree is rebuilt")
    adr, num = int(m.body_bvhadr[body]), int(m.body_bvhnum[body])
    if num < 5:
        return
    rows = slice(adr, adr + num)
    leaves = np.flatnonzero(m.bvh_nodeid[rows] >= 0)
    ids = m.bvh_nodeid[rows][leaves].copy()
    boxes = m.bvh_aabb[rows][leaves].copy()
    if 2 * len(ids) - 1 != num:  # a binary tree: what the compiler builds
        raise ValueError(f"body {body}'s tree is not a binary tree of its leaves")
    lo, hi = boxes[:, :3] - boxes[:, 3:], boxes[:, :3] + boxes[:, 3:]

    child = np.full((num, 2), -1, dtype=m.bvh_child.dtype)
    nodeid = np.full(num, -1, dtype=m.bvh_nodeid.dtype)
    depth = np.zeros(num, dtype=m.bvh_depth.dtype)
    aabb = np.zeros((num, 6))
    stack = [(np.arange(len(ids)), 0, -1, 0)]  # leaves, depth, parent, side
    count = 0
    while stack:
        sel, level, parent, side = stack.pop()
        node = count
        count += 1
        depth[node] = level
        if parent >= 0:
            child[parent, side] = node
        if len(sel) == 1:
            nodeid[node] = ids[sel[0]]
            aabb[node] = boxes[sel[0]]
            continue
        left = _split(lo[sel], hi[sel], ids[sel])
        # pre-order: the left child is numbered next, so it is popped first
        stack.append((sel[~left], level + 1, node, 1))
        stack.append((sel[left], level + 1, node, 0))
    # internal boxes, children before parents: the union, rounded outwards
    for node in range(num - 1, -1, -1):
        if nodeid[node] >= 0:
            continue
        c = aabb[child[node]]
        n_lo = np.min(c[:, :3] - c[:, 3:], axis=0)
        n_hi = np.max(c[:, :3] + c[:, 3:], axis=0)
        centre = (n_lo + n_hi) / 2
        # a few ulps of the coordinates out: rounding may not shrink a box
        tol = 8 * np.finfo(float).eps * np.maximum(np.abs(n_lo), np.abs(n_hi))
        half = np.maximum(n_hi - centre, centre - n_lo) + tol
        aabb[node] = np.concatenate([centre, half])
    m.bvh_child[rows] = child
    m.bvh_nodeid[rows] = nodeid
    m.bvh_depth[rows] = depth
    m.bvh_aabb[rows] = aabb
