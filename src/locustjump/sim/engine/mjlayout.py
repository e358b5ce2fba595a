"""Where MuJoCo keeps the few ``mjData``/``mjModel`` fields that compiled code
reads through raw pointers (:mod:`locustjump.sim.engine.callback`): offsets computed
from MuJoCo's own struct descriptions (``mujoco.introspect``) and checked
against a live model and data."""

from __future__ import annotations

import ctypes
from typing import Any

import mujoco
from mujoco.introspect import ast_nodes, structs

_CTYPES = {"mjtNum": ctypes.c_double, "mjtSize": ctypes.c_int64, "int": ctypes.c_int,
           "size_t": ctypes.c_size_t, "uintptr_t": ctypes.c_size_t,
           "mjtBool": ctypes.c_ubyte, "mjtByte": ctypes.c_ubyte,
           "float": ctypes.c_float, "unsigned int": ctypes.c_uint}  # fmt: skip


def _struct(name: str, *upto: str) -> type[ctypes.Structure]:
    """A ctypes mirror of MuJoCo's struct ``name`` (its fields up to the last of
    ``upto``; all without), from ``mujoco.introspect``."""

    fields, missing = [], set(upto)
    for f in structs.STRUCTS[name].fields:
        fields.append((f.name, _ctype(f.type, ast_nodes)))
        missing.discard(f.name)
        if upto and not missing:
            break
    return type(name, (ctypes.Structure,), {"_fields_": fields})


def _ctype(t: Any, ast_nodes: Any) -> Any:  # a ctypes type
    if isinstance(t, ast_nodes.PointerType):
        return ctypes.c_void_p
    if isinstance(t, ast_nodes.ArrayType):
        inner = _ctype(t.inner_type, ast_nodes)
        for n in reversed(t.extents):
            inner = inner * n
        return inner
    if t.name in _CTYPES:
        return _CTYPES[t.name]
    return _struct(t.name)


def offsets(nuserdata: int) -> tuple[int, int, int, int, int, int] | None:
    """Offsets of mjData's qpos, ctrl, sensordata, userdata and warning and of
    mjModel's nuserdata, checked against a live model (with ``nuserdata``) and
    data; None where they do not match or MuJoCo's descriptions are not known."""
    try:
        data = _struct("mjData", "qpos", "ctrl", "sensordata", "userdata")
        model = _struct("mjModel", "nuserdata")
        m = mujoco.MjModel.from_xml_string(
            f'<mujoco><size nuserdata="{nuserdata}"/><worldbody><body>'
            '<joint name="j"/><geom size=".1"/><site name="s"/></body></worldbody>'
            '<actuator><motor joint="j"/></actuator>'
            '<sensor><touch site="s"/></sensor></mujoco>'
        )
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        raw = data.from_address(d._address)
        mraw = model.from_address(m._address)
        # (read through the offsets, known): each must match
        pairs = (
            (raw.qpos, d.qpos.ctypes.data),
            (raw.ctrl, d.ctrl.ctypes.data),
            (raw.sensordata, d.sensordata.ctypes.data),
            (raw.userdata, d.userdata.ctypes.data),
            (mraw.nuserdata, nuserdata),
            # warning[0].number, 4 bytes into the array of {lastinfo, number}
            (data.warning.offset, d.warning.number.ctypes.data - d._address - 4),
        )
    except Exception:  # an unknown type or layout: this path is off
        return None
    if not all(read == known for read, known in pairs):
        return None
    fields = ("qpos", "ctrl", "sensordata", "userdata", "warning")
    return (*(getattr(data, f).offset for f in fields), model.nuserdata.offset)
