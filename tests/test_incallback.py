"""The compiled path with the controllers inside MuJoCo's control callback
(:mod:`locustjump.sim.engine.incallback`) against its step-by-step loop
(:func:`locustjump.sim.engine.compiled.run_compiled`): the same kernels on one episode's
slices, so every record, failure step and step count agrees bit for bit."""

import ast
import ctypes
import dataclasses
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest
from mujoco.batch import Batch

from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine import callback, incallback, mjlayout
from locustjump.sim.engine.compiled import run_compiled
from locustjump.sim.engine.incallback import run_incallback
from locustjump.sim.engine.job import STEP_RECORDS
from locustjump.sim.engine.rollout import RolloutJob, StartStates
from locustjump.tasks import get_behaviour
from locustjump.tasks.composed import SwitchingController

needs_layout = pytest.mark.skipif(
    not incallback.AVAILABLE, reason="this MuJoCo's mjData layout is not known"
)


def test_the_kernels_digest_is_current():
    """callback.py's cached compiled code calls the kernels (kernels.py and
    the cephes.py functions they call), whose changes Numba's cache does not
    notice: a change there must come with this digest."""
    assert callback.kernels_digest() == callback.KERNELS_SHA256, (
        "kernels.py or cephes.py changed: set callback.KERNELS_SHA256 = "
        f'"{callback.kernels_digest()}"'
    )
    # importable from the engine's module, as before the callback had its own
    assert incallback.KERNELS_SHA256 is callback.KERNELS_SHA256


def test_the_cephes_digest_is_current():
    """kernels.py's cached code holds cephes.py's exp and tanh, compiled in:
    a change to cephes.py must come with kernels.py's line naming it (else
    the kernels are compiled afresh in every process)."""
    from locustjump.sim import cephes, kernels

    digest = hashlib.sha256(Path(cephes.__file__).read_bytes()).hexdigest()
    assert digest == kernels.CEPHES_SHA256, (
        f'cephes.py changed: set kernels.CEPHES_SHA256 = "{digest}"'
    )
    assert kernels.CACHE


def test_the_in_callback_digest_covers_every_file_of_the_kernels(tmp_path):
    """The files the kernels come from are kernels.py and cephes.py, and a
    change to any one of them changes the digest that guards callback.py's
    cached code."""
    from locustjump.sim import cephes, kernels

    assert kernels.SOURCES == (kernels.__file__, cephes.__file__)
    copies = [tmp_path / Path(s).name for s in kernels.SOURCES]
    for source, copy in zip(kernels.SOURCES, copies, strict=True):
        copy.write_bytes(Path(source).read_bytes())
    paths = tuple(map(str, copies))
    digest = callback.kernels_digest(paths)
    assert digest == callback.kernels_digest()
    for copy in copies:
        before = copy.read_bytes()
        copy.write_bytes(before + b"#")
        assert callback.kernels_digest(paths) != digest, copy
        copy.write_bytes(before)


def _imports(path: str) -> list[str]:
    """What the module at ``path`` imports from locustjump, each name whole
    (``from locustjump.sim import cephes``: ``locustjump.sim.cephes``)."""
    tree = ast.parse(Path(path).read_text())
    names = [
        f"{n.module}.{a.name}"
        for n in ast.walk(tree)
        if isinstance(n, ast.ImportFrom) and n.module
        for a in n.names
    ] + [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    return [m for m in names if m.split(".")[0] == "locustjump"]


def test_the_cached_kernels_read_nothing_from_another_module():
    """Numba's cache keys a kernel's machine code on its own file, and the
    globals it reads are frozen into that code: a constant imported from
    another module (MAX_DELTA from actuation.py, once) could change there
    while the cached kernel kept the old value. kernels.py imports from
    locustjump only cephes.py, whose digest it carries (above), cephes.py
    nothing, and the actuation rule's limit is the kernels' own."""
    from locustjump.sim import actuation, cephes, kernels

    ours = _imports(kernels.__file__)
    assert ours and all(m.startswith("locustjump.sim.cephes") for m in ours), ours
    assert not _imports(cephes.__file__)
    assert actuation.MAX_DELTA is kernels.MAX_DELTA


def test_a_changed_cephes_turns_the_kernels_cache_off(tmp_path):
    """A copy of the package with cephes.py changed and kernels.py not: its
    kernels are not cached (and it says so); the copy as it is: cached."""
    for changed in (False, True):
        src = tmp_path / str(changed) / "src"
        shutil.copytree(Path(incallback.__file__).parents[2], src / "locustjump",
                        ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
        if changed:
            with open(src / "locustjump" / "sim" / "cephes.py", "a") as f:
                f.write("# changed\n")
        r = subprocess.run(
            [sys.executable, "-c", "from locustjump.sim import kernels as k; "
             "print(k.CACHE, k.__file__)"],
            env={**os.environ, "PYTHONPATH": str(src),
                 "NUMBA_CACHE_DIR": str(tmp_path / "numba")},
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert r.returncode == 0, r.stderr
        cached, where = r.stdout.split()
        assert Path(where).is_relative_to(src)
        assert cached == str(not changed)
        assert ("CEPHES_SHA256" in r.stderr) is changed, r.stderr


def test_the_field_offsets_are_those_of_this_mujoco():
    # the literals the compiled callback was built with, against the offsets
    # read from MuJoCo's own struct descriptions and checked on live data
    assert mjlayout.offsets(callback.NUSERDATA) == callback.OFFSETS
    assert callback.AVAILABLE and incallback.AVAILABLE


def _both(job: RolloutJob, threads: int = 2):
    m = lm.load_model(job.model_params)
    batch = Batch(m, job.n_episodes, threads, persistent=True)
    return run_compiled(batch, job), run_incallback(batch, job)


def _same(a, b) -> None:
    assert a.records.keys() == b.records.keys()
    for k in a.records:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    np.testing.assert_array_equal(a.unstable, b.unstable)
    np.testing.assert_array_equal(a.steps, b.steps)
    assert a.control_steps == b.control_steps


def _getup_job(substeps: int, controller, n: int, steps: int, seed: int = 0):
    p = lm.LocustParams(substeps=substeps)
    starts = get_behaviour("getup").start_states(p)
    rng = np.random.default_rng(seed)
    params = rng.uniform(-1, 1, (n, controller.num_params))
    return RolloutJob(p, controller, params, starts.take(np.arange(n) % len(starts)),
                      steps, STEP_RECORDS, engine="numba")  # fmt: skip


@pytest.mark.parametrize("substeps", [1, 3])
@needs_layout
def test_networks_in_the_callback_give_the_step_loops_numbers(substeps):
    a, b = _both(_getup_job(substeps, MLP(), 12, 150))
    _same(a, b)
    assert not a.unstable.any()


@pytest.mark.parametrize("every", [120, 7])
@needs_layout
def test_the_switcher_in_the_callback_gives_the_step_loops_numbers(every):
    simple = MLP().random_genomes(np.random.default_rng(3), 3)
    ctl = SwitchingController(simple=simple, every=every)
    a, b = _both(_getup_job(3, ctl, 8, 260, seed=every))
    _same(a, b)
    assert len(np.unique(b["memory"])) > 1  # it switched


@needs_layout
def test_blowups_are_simulated_again_on_the_step_loop():
    """qvel 100 fails at control step 57, 1e30 at once: their records and
    steps are the step loop's; the others are those of a run without them."""
    p = lm.LocustParams()
    starts = StartStates.ready(lm.load_model(p)).take([0, 0, 0, 0])
    starts.qvel[:, :] = np.array([0.0, 100.0, 0.0, 1e30])[:, None]
    genome = MLP().random_genomes(np.random.default_rng(1), 1, 3.0)
    job = RolloutJob(p, MLP(), np.repeat(genome, 4, 0), starts, 120, STEP_RECORDS,
                     engine="numba")  # fmt: skip
    a, b = _both(job)
    _same(a, b)
    assert b.unstable.tolist() == [False, True, False, True]
    assert 1 < b.steps[1] < 120
    calm = run_incallback(Batch(lm.load_model(p), 1, 1, persistent=True),
                          dataclasses.replace(job, params=job.params[:1],
                                              starts=starts.take([0])))  # fmt: skip
    np.testing.assert_array_equal(b["qpos"][2], calm["qpos"][0])


@needs_layout
def test_chunked_calls_under_a_progress_bar_change_nothing():
    job = _getup_job(3, MLP(), 6, 250)
    plain = run_incallback(Batch(lm.load_model(job.model_params), 6, 2,
                                 persistent=True), job)  # fmt: skip
    _, chunked = _both(dataclasses.replace(job, label="test"))
    _same(plain, chunked)


@needs_layout
def test_threads_and_batch_splits_change_nothing():
    job = _getup_job(3, MLP(), 10, 100, seed=5)
    _, one = _both(job, threads=1)
    _, two = _both(job, threads=2)
    _same(one, two)
    parts = [_both(j, threads=2)[1] for j in job.split(3)]
    for k in one.records:
        np.testing.assert_array_equal(np.concatenate([p[k] for p in parts]), one[k])


@needs_layout
def test_another_control_callback_is_respected():
    """A callback the user installed stays, and the rollout runs on the step
    loop (same numbers)."""
    calls = []
    theirs = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)(
        lambda m, d: calls.append(1)
    )
    job = _getup_job(3, MLP(), 4, 20)
    want, _ = _both(job)
    mujoco.set_mjcb_control(theirs)
    try:
        got = run_incallback(Batch(lm.load_model(job.model_params), 4, 1,
                                   persistent=True), job)  # fmt: skip
        assert mujoco.get_mjcb_control() is not None
    finally:
        mujoco.set_mjcb_control(None)
    assert calls  # theirs ran
    for k in want.records:
        np.testing.assert_array_equal(got[k], want[k])


@needs_layout
def test_the_callback_leaves_other_simulations_alone():
    """Installed, it ignores a model without userdata and a locust whose
    marker is not set: both step as without it; afterwards none is left."""
    p = lm.LocustParams()
    m = lm.load_model(p)
    other = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body><freejoint/><geom size='.1'/></body>"
        "</worldbody></mujoco>"
    )
    runs = []
    for installed in (False, True):
        d, od = mujoco.MjData(m), mujoco.MjData(other)
        d.ctrl[:] = 0.3
        if installed:
            mujoco.set_mjcb_control(callback._control.ctypes)
        try:
            mujoco.mj_step(m, d, 30)
            mujoco.mj_step(other, od, 30)
        finally:
            mujoco.set_mjcb_control(None)
        runs.append((d.qpos.copy(), d.ctrl.copy(), od.qpos.copy()))
    for x, y in zip(*runs, strict=True):
        np.testing.assert_array_equal(x, y)
    job = _getup_job(3, MLP(), 2, 5)
    run_incallback(Batch(m, 2, 1, persistent=True), job)
    assert mujoco.get_mjcb_control() is None
