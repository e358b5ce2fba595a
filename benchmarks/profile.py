"""Where a training run's wall time goes: a sampling profile (py-spy) of
``locustjump train BEHAVIOUR``, summed into a table of the main thread's time.

    python benchmarks/profile.py --behaviour getup --generations 3

Needs ``py-spy`` (``pip install py-spy``; it is not a dependency of the
package). Samples the main thread at ``--rate`` Hz with native frames; each
sample is put in the first category (below) whose function is on its stack,
innermost first. ``Batch.rollout`` is the main thread waiting for MuJoCo's C
threads to step the physics: everything else is Python and NumPy work of the
engine, the GA and the run directory. Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

# (category, pattern matched against a frame "function (file:line)"), checked
# from the innermost frame outwards.
CATEGORIES = [
    (
        "physics (Batch.rollout, C threads)",
        r"^Batch\.(step|rollout) |\((mujoco/)?_batch\.|libmujoco",
    ),
    ("network (MLP / switcher)", r"^(MLP\.|SwitchingController\.)"),
    ("sensors (paper_inputs)", r"^(paper_inputs|up_axis_in_body) "),
    ("actuation (apply_deltas)", r"^apply_deltas "),
    ("recording (_Recorder)", r"^_Recorder\."),
    ("engine loop (instability check, bookkeeping)", r"^_run_batch "),
    ("start states (settling)", r"^(settle|rolled_starts|extended_start) "),
    (
        "fitness and metrics",
        r"^(\w+\.)?(fitness|episode_fitness|kick_fitness|metrics) ",
    ),
    ("GA (ask / tell)", r"^RCGA\."),
    ("checkpoint, best genome, metrics.csv", r"^_Run\.|^BestGenome\.save|_atomic"),
    ("fitness figure", r"fitness_figure"),
    ("model compile", r"^(load_model|to_mjcf|_settle) "),
    ("imports and start-up", r"importlib|^<module> "),
]


def categorise(raw: str, main_thread: str | None = None) -> Counter[str]:
    pats = [(name, re.compile(p)) for name, p in CATEGORIES]
    counts: Counter[str] = Counter()
    for line in raw.splitlines():
        stack, _, n = line.rpartition(" ")
        frames = stack.split(";")
        if main_thread is not None and frames[0].split(":")[0] != main_thread:
            continue
        cat = "other"
        for fr in reversed(frames):
            hit = None
            for name, pat in pats:
                if pat.search(fr):
                    hit = name
                    break
            if hit is not None:
                cat = hit
                break
        counts[cat] += int(n)
    return counts


def mujoco_timers(steps: int = 3000) -> None:
    """Inside ``mj_step``: MuJoCo's own timers over the rule-based 3000-step
    run (contacts, flights and landings), replayed on one ``MjData``."""
    import mujoco

    from locustjump.sim import model as lm
    from locustjump.tasks.reference import run_rules

    p = lm.LocustParams()
    m = lm.load_model(p)
    ctrl = run_rules(steps=steps).ctrl
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    ncon = 0
    for t in range(1, steps + 1):
        d.ctrl[:] = ctrl[t]
        for _ in range(p.substeps):
            mujoco.mj_step(m, d)
            ncon += d.ncon
    T = mujoco.mjtTimer
    step = d.timer[T.mjTIMER_STEP]
    per = step.duration / step.number * 1e6
    print(f"\n`mj_step` internals ({step.number} steps of the rule-based run, "
          f"{ncon / step.number:.2f} contacts a step on average): "
          f"{per:.2f} us a step\n")  # fmt: skip
    print("| stage | us a step | share |")
    print("| --- | --- | --- |")
    rows = (
        "POS_KINEMATICS POS_INERTIA POS_COLLISION POS_MAKE POS_PROJECT VELOCITY "
        "ACTUATION CONSTRAINT ADVANCE"
    ).split()
    for name in rows:
        tm = d.timer[getattr(T, f"mjTIMER_{name}")]
        us = tm.duration / max(tm.number, 1) * 1e6
        print(f"| {name.lower()} | {us:.2f} | {100 * us / per:.0f} % |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--behaviour", default="getup")
    ap.add_argument("--generations", type=int, default=3)
    ap.add_argument("--rate", type=int, default=200, help="samples per second")
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument(
        "--mujoco-timers", action="store_true", help="only time mj_step's stages"
    )
    args = ap.parse_args()
    if args.mujoco_timers:
        mujoco_timers()
        return 0
    spy = shutil.which("py-spy") or str(Path(sys.executable).parent / "py-spy")
    if not Path(spy).exists():
        print(
            "profile.py: error: py-spy not found (pip install py-spy)", file=sys.stderr
        )
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "profile.raw"
        run = Path(tmp) / "run"
        cmd = [spy, "record", "--native", "--threads", "--rate", str(args.rate),
               "--format", "raw", "-o", str(raw), "--", sys.executable, "-m",
               "locustjump.cli", "train", args.behaviour, "--generations",
               str(args.generations), "--out", str(run), "--quiet"]  # fmt: skip
        if args.threads:
            cmd += ["--threads", str(args.threads)]
        subprocess.run(cmd, check=True, capture_output=True)
        text = raw.read_text()
    # frames[0] is "thread (TID): NAME" (or "thread (TID)" before it is named)
    names = {line.split(";", 1)[0] for line in text.splitlines()}
    main_thread = next(t for t in names if t.endswith(": MainThread")).split(":")[0]
    counts = categorise(text, main_thread)
    total = sum(counts.values())
    print(f"`locustjump train {args.behaviour} --generations {args.generations}`, "
          f"{total} samples of the main thread at {args.rate} Hz\n")  # fmt: skip
    print("| where | share of wall time |")
    print("| --- | --- |")
    for name, n in counts.most_common():
        print(f"| {name} | {100 * n / total:.1f} % |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
