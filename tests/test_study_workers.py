"""Several processes train one study at once: each takes the runs no other
process holds, waits for the ones it builds on, and returns when the whole
study is done; the runs are the ones one process makes."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_same_run
from locustjump import rundir
from locustjump.runs.study import _next_run, format_duration, run_study, states
from locustjump.runs.study_plan import status
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train
from locustjump.sim.engine.backends import ThreadBackend

REPO = Path(__file__).resolve().parents[1]

#: holds the lock of a directory until its stdin closes (another worker)
HOLD = """
import fcntl, os, sys
fd = os.open(sys.argv[1], os.O_RDONLY)
fcntl.flock(fd, fcntl.LOCK_EX)
print("locked", flush=True)
sys.stdin.read()
"""


def _hold(directory: Path) -> subprocess.Popen:
    directory.mkdir(parents=True, exist_ok=True)
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(directory)],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                              text=True)  # fmt: skip
    assert holder.stdout.readline().strip() == "locked"
    return holder


def _release(holder: subprocess.Popen) -> None:
    holder.stdin.close()
    holder.wait(timeout=30)


def _run_releasing(study, holder: subprocess.Popen, on_wait=None):
    """``run_study`` on one thread, releasing ``holder`` when it first waits
    (``on_wait()`` first); (its final states, the lines it logged)."""
    lines: list[str] = []

    def log(line: str) -> None:
        lines.append(line)
        if line.startswith("waiting for") and holder.poll() is None:
            if on_wait:
                on_wait()
            _release(holder)

    try:
        with ThreadBackend(1) as backend:
            final = run_study(study, backend=backend, progress=False, log=log,
                              poll=0.05)  # fmt: skip
    finally:
        if holder.poll() is None:
            _release(holder)
    return final, lines


def _study(tmp_path: Path, name: str, seeds: str | None = None):
    """Study file ``name`` with its runs and table under ``tmp_path``."""
    text = (REPO / "studies" / f"{name}.toml").read_text()
    lines = [
        f'root = "{tmp_path / "runs"}"' if ln.startswith("root =")
        else f'out = "{tmp_path / "out"}"' if ln.startswith("out =")
        else ln
        for ln in text.splitlines()
    ]  # fmt: skip
    path = tmp_path / f"{name}.toml"
    path.write_text("\n".join(lines) + "\n")
    return load_study(path, seeds)


def test_in_use_names_the_process_that_holds_a_directory(tmp_path):
    d = tmp_path / "run"
    holder = _hold(d)
    try:
        assert rundir.in_use(d) == f"process {holder.pid}"
        with pytest.raises(rundir.InUse, match=f"in use by process {holder.pid}"):
            with rundir.locked(d):
                pass
    finally:
        _release(holder)
    assert rundir.in_use(d) is None
    with rundir.locked(d):
        assert rundir.in_use(d) is None  # this process's own lock
    assert rundir.in_use(tmp_path / "absent") is None


def test_a_run_another_process_trains_is_left_to_it(tmp_path):
    """rcga seed 0 is held by another process: this one trains the other
    runs, says whom it waits for, and, once that process is gone without
    finishing it, trains it too, as one process alone would."""
    study = _study(tmp_path, "example", "0-1")
    held = study.arms["rcga"].run_dir(0)
    holder = _hold(held)
    shown: list[str] = []
    final, lines = _run_releasing(study, holder, lambda: shown.append(status(study)))
    trained = [ln.split(" -> ")[0] for ln in lines if ln.startswith("[")]
    assert trained == ["[1] random, seed 0", "[2] rcga, seed 1",
                       "[3] random, seed 1", "[4] rcga, seed 0"]  # fmt: skip
    wait = [ln for ln in lines if ln.startswith("waiting")]
    assert wait == [
        f"waiting for 1 run(s) other processes train: rcga seed 0 "
        f"(process {holder.pid})"
    ]
    assert f"| rcga | to do, process {holder.pid} | done |" in shown[0]
    assert all(st.finished for st in final)
    alone = tmp_path / "alone"
    train(study.arms["rcga"].config(0), alone, progress=False)
    assert_same_run(held, alone)


def test_a_run_waits_for_the_runs_it_builds_on(tmp_path):
    """The pipeline and the repertoire are not started while the simple
    behaviours they build on are another process's; the one network is."""
    study = _study(tmp_path, "repertoire-composition", "0")
    left = states(study)
    first, _ = _next_run(study, left)
    assert first is not None and (first.arm, first.seed) == ("kick", 0)
    simples = ("kick", "kick-repertoire", "getup", "return-legs")
    holders = [_hold(study.arms[a].run_dir(0)) for a in simples]
    try:
        nxt, held = _next_run(study, left)
        assert nxt is not None and nxt.arm == "monolithic"
        assert held == [f"{a} seed 0 (process {h.pid})"
                        for a, h in zip(simples, holders, strict=True)]  # fmt: skip
        mono = [s for s in left if s.arm != "monolithic"]
        assert _next_run(study, mono)[0] is None
    finally:
        for h in holders:
            _release(h)
    assert _next_run(study, left)[0] == first


def test_a_run_made_between_the_look_and_the_lock_is_left_to_its_maker(
    tmp_path, monkeypatch
):
    """Another process locks (and starts) a run just after this one looked:
    whatever ``train`` then says (here: the directory holds a run), the run
    is left to that process, not a crash."""
    import locustjump.runs.study as study_mod
    from locustjump.errors import UserError

    study = _study(tmp_path, "example", "0")
    held = study.arms["rcga"].run_dir(0)
    holder = _hold(held)
    real_in_use, real_train = rundir.in_use, study_mod.train
    looks = {"n": 0}

    def late_look(d):  # the first look misses the lock
        looks["n"] += 1
        return None if looks["n"] == 1 else real_in_use(d)

    def train(cfg, out, **kw):
        if out == held and holder.poll() is None:
            raise UserError(f"--out {out}: directory holds a run")
        return real_train(cfg, out, **kw)

    monkeypatch.setattr(rundir, "in_use", late_look)
    monkeypatch.setattr(study_mod, "train", train)
    final, lines = _run_releasing(study, holder)
    assert any("rcga, seed 0: left to its trainer" in ln for ln in lines), lines
    assert all(st.finished for st in final)


def test_status_says_what_is_left_at_the_pace_of_its_trainers(tmp_path):
    """rcga seed 0 stopped after 2 of 4 generations: with no process on it,
    --status says so; held by one, it gives the time left at that run's
    pace (its generations' median control steps/s)."""
    study = _study(tmp_path, "example", "0")
    arm = study.arms["rcga"]
    run = arm.run_dir(0)
    train(arm.config(0), run, progress=False, stop_after=2)
    now = states(study)
    left = sum(st.steps_left for st in now)
    assert left == 6 * now[0].steps_per_generation  # rcga's 2 left, random's 4
    assert status(study).endswith(
        f"0 of 2 runs done, {left:,} control steps left; no process is training it now"
    )
    rate = float(np.median(rundir.read_metrics(run / rundir.METRICS)["steps_per_s"]))
    holder = _hold(run)
    try:
        last = status(study).splitlines()[-1]
    finally:
        _release(holder)
    assert last == (
        f"0 of 2 runs done, {left:,} control steps left: about "
        f"{format_duration(left / rate)} at the pace of the 1 process training it now "
        f"({rate:,.0f} control steps/s; scoring not counted)"
    )


def test_status_forecasts_the_runs_left_as_its_trainers_take_them(
    tmp_path, monkeypatch
):
    """Two processes, each on a run with 2 of 4 generations left; random
    seed 1 done, rcga seed 1 to do. They take the runs as run_study does:
    both finish theirs, one takes rcga seed 1 and the other has nothing left,
    so the study takes 6 generations' time, not (2 + 2 + 4) / 2, the last 4
    with one process at work. A third process on rcga seed 1, no generation
    timed yet, trains at the others' pace: 4 generations' time."""
    import locustjump.runs.study_plan as plan

    study = _study(tmp_path, "example", "0-1")
    rcga, rand = study.arms["rcga"], study.arms["random"]
    for arm in (rcga, rand):
        train(arm.config(0), arm.run_dir(0), progress=False, stop_after=2)
    train(rand.config(1), rand.run_dir(1), progress=False)
    holders = [_hold(rcga.run_dir(0)), _hold(rand.run_dir(0))]
    try:
        training = [st for st in states(study) if st.seed == 0]
        assert plan.pace(training) == [
            float(
                np.median(rundir.read_metrics(st.path / rundir.METRICS)["steps_per_s"])
            )
            for st in training
        ]
        monkeypatch.setattr(plan, "pace", lambda runs: [1.0 for r in runs if r.done])
        last = status(study).splitlines()[-1]
        # a third process starts rcga seed 1: untimed, at the others' pace
        holders.append(_hold(rcga.run_dir(1)))
        third = status(study).splitlines()[-1]
    finally:
        for h in holders:
            _release(h)
    g = states(study)[0].steps_per_generation  # 1 control step/s a process
    assert last == (
        f"1 of 4 runs done, {8 * g:,} control steps left: about "
        f"{format_duration(6 * g)} at the pace of the 2 processes training it now "
        "(1 control steps/s each, taking the next run it may; the last "
        f"{format_duration(4 * g)} of it with fewer than 2 at work; scoring not "
        "counted)"
    )
    assert f"about {format_duration(4 * g)} at the pace of the 3 processes" in third


def test_the_forecast_knows_what_each_run_builds_on(tmp_path):
    """The repertoire study's seed 0, nothing trained: the switchers wait on
    their own seed's simple runs (by position in the study's order), the
    simple runs and the one network on none; a held run is marked."""
    from locustjump.runs.study_plan import _jobs

    study = _study(tmp_path, "repertoire-composition", "0")
    todo = states(study)
    at = {st.arm: i for i, st in enumerate(todo)}
    jobs = _jobs(study, todo, {todo[at["kick"]].path}, 2.0)
    after = {st.arm: {todo[i].arm for i in job.after}
             for st, job in zip(todo, jobs, strict=True)}  # fmt: skip
    assert after == {
        "kick": set(), "kick-repertoire": set(), "getup": set(),
        "return-legs": set(), "monolithic": set(),
        "pipeline": {"kick", "getup", "return-legs"},
        "repertoire": {"kick-repertoire", "getup", "return-legs"},
    }  # fmt: skip
    assert [job.held for job in jobs] == [st.arm == "kick" for st in todo]
    assert [job.seconds for job in jobs] == [st.steps_left / 2.0 for st in todo]
