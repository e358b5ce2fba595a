"""Where MuJoCo keeps the fields the compiled callback reads through raw
pointers (``sim/engine/mjlayout.py``): the offsets of this MuJoCo, checked on
live data, and ``None`` (the callback path off) wherever they do not match."""

import ctypes

import mujoco
import pytest
from mujoco.introspect import ast_nodes, structs

from locustjump.sim import model as lm
from locustjump.sim.engine import callback, mjlayout


def test_the_offsets_point_at_the_fields_of_a_live_locust():
    """Read through the offsets, a simulation's bytes give its own arrays."""
    off = mjlayout.offsets(3)
    assert off == callback.OFFSETS
    m = lm.load_model()
    d = mujoco.MjData(m)
    qpos, ctrl, sens, user, warn, nuser = off

    def pointer(at: int) -> int:
        return ctypes.c_void_p.from_address(d._address + at).value

    assert pointer(qpos) == d.qpos.ctypes.data
    assert pointer(ctrl) == d.ctrl.ctypes.data
    assert pointer(sens) == d.sensordata.ctypes.data
    assert pointer(user) == d.userdata.ctypes.data
    # warning[i] is {lastinfo, number}: its number 4 bytes in, 8 bytes each
    i = int(mujoco.mjtWarning.mjWARN_BADQACC)
    d.warning[i].number = 7
    assert ctypes.c_int.from_address(d._address + warn + 8 * i + 4).value == 7
    assert ctypes.c_int64.from_address(m._address + nuser).value == m.nuserdata == 3


def test_any_number_of_user_slots_has_the_same_offsets():
    assert mjlayout.offsets(1) == mjlayout.offsets(7) == callback.OFFSETS


def test_a_layout_that_does_not_match_turns_the_path_off(monkeypatch):
    """A wrong size for MuJoCo's numbers moves every field: no offsets."""
    monkeypatch.setitem(mjlayout._CTYPES, "mjtNum", ctypes.c_float)
    assert mjlayout.offsets(3) is None


@pytest.mark.parametrize("name", ["int", "mjtSize"])
def test_each_size_counts(monkeypatch, name):
    monkeypatch.setitem(mjlayout._CTYPES, name, ctypes.c_int16)
    assert mjlayout.offsets(3) is None


def test_unknown_descriptions_turn_the_path_off(monkeypatch):
    monkeypatch.delitem(structs.STRUCTS, "mjModel")
    assert mjlayout.offsets(3) is None


def test_a_struct_stops_at_the_last_field_asked_for():
    names = [f.name for f in structs.STRUCTS["mjData"].fields]
    upto = mjlayout._struct("mjData", "userdata", "qpos")
    assert [f for f, _ in upto._fields_] == names[: names.index("userdata") + 1]
    whole = mjlayout._struct("mjSolverStat")  # without a field named: all
    assert len(whole._fields_) == len(structs.STRUCTS["mjSolverStat"].fields) > 2
    assert whole.__name__ == "mjSolverStat" and issubclass(whole, ctypes.Structure)


def test_the_ctypes_of_a_field():
    ctype = mjlayout._ctype
    assert ctype(ast_nodes.ValueType("mjtNum"), ast_nodes) is ctypes.c_double
    assert ctype(ast_nodes.ValueType("mjtSize"), ast_nodes) is ctypes.c_int64
    assert ctype(ast_nodes.ValueType("mjtByte"), ast_nodes) is ctypes.c_ubyte
    pointer = ast_nodes.PointerType(ast_nodes.ValueType("mjtNum"))
    assert ctype(pointer, ast_nodes) is ctypes.c_void_p
    # int x[2][3]: two rows of three, the first extent outermost
    grid = ctype(ast_nodes.ArrayType(ast_nodes.ValueType("int"), (2, 3)), ast_nodes)
    assert grid._length_ == 2 and grid._type_._length_ == 3
    assert grid._type_._type_ is ctypes.c_int
    stat = ctype(ast_nodes.ValueType("mjWarningStat"), ast_nodes)
    assert [f for f, _ in stat._fields_] == ["lastinfo", "number"]
    assert ctypes.sizeof(stat) == 8
