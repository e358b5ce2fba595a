"""Mutation testing of the core modules (issue #48), with mutmut 3.

For each module below, mutmut changes one token at a time (a comparison, an
operator, a constant, a string, an argument) and runs the tests that reach
the mutated function (mutmut's per-function selection, measured once per
module by a "stats" run) from the module's *focused* test files only, never
the whole suite. A mutant no test notices is a behaviour no test states.

Each module runs in its own scratch directory ``.mutation/<module>/``
(``src``, ``tests`` and ``scripts`` linked, ``pyproject.toml`` with the module's
``[tool.mutmut]``; mutmut copies and mutates under ``mutants/`` there).
Numba's cache goes to a directory of that scratch run (``NUMBA_CACHE_DIR``),
so compiled code cached from the checkout is never run in place of a mutant.

``docs/mutation.md`` is written from the results of every module that has
run: mutants, killed (a test failed; timeouts count), equivalent (listed in
:data:`EQUIVALENT` of ``scripts/mutation_equivalent.py``, with the reason),
survived (no test failed, or no test reached it) and the kill rate
``killed / (mutants - equivalent)``.

    python scripts/mutation.py                  # every module (under an hour)
    python scripts/mutation.py evo/rcga.py      # one module (minutes)
    python scripts/mutation.py evo/rcga.py --survivors   # rerun what survived

``make mutation`` runs every module; it is not part of ``make test``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from fnmatch import fnmatch
from pathlib import Path
from typing import TypedDict

from mutation_equivalent import EQUIVALENT

ROOT = Path(__file__).resolve().parent.parent
SCRATCH = ROOT / ".mutation"
DOC = ROOT / "docs" / "mutation.md"
#: the wall time and date of the last run of every module from scratch
LAST_RUN = SCRATCH / "last-run.txt"
BIN = Path(sys.executable).parent

#: module (under src/locustjump) -> the focused test files that state it
MODULES: dict[str, tuple[str, ...]] = {
    "evo/rcga.py": (
        "tests/test_rcga.py",
        "tests/test_rcga_behaviour.py",
        "tests/test_optimizers.py",
    ),
    "rundir/metrics.py": ("tests/test_metrics_contract.py",),
    "rundir/config.py": ("tests/test_config_contract.py", "tests/test_migrations.py"),
    "sim/sensors.py": (
        "tests/test_sensors_inputs.py",
        "tests/test_sensors_controller.py",
    ),
    "sim/actuation.py": (
        "tests/test_actuation_rule.py",
        "tests/test_sensors_controller.py",
    ),
    "rundir/checkpoint.py": ("tests/test_checkpoint_contract.py",),
    "evo/base.py": ("tests/test_optimizer_contract.py", "tests/test_rcga_behaviour.py"),
    "evo/random_search.py": ("tests/test_optimizer_contract.py",),
    "evo/cma.py": ("tests/test_cma_contract.py",),
    "evo/__init__.py": ("tests/test_optimizer_contract.py",),
    "tasks/kick.py": ("tests/test_kick_fitness.py", "tests/test_qd.py"),
    "tasks/getup.py": ("tests/test_task_fitness.py",),
    "tasks/return_legs.py": ("tests/test_task_fitness.py",),
    "tasks/base.py": ("tests/test_task_fitness.py",),
    "tasks/composed.py": ("tests/test_task_fitness.py",),
    # the statistics every comparison and every claim of docs/science.md rests on
    "present/stats.py": ("tests/test_stats.py",),
    # the study table those claims are read from: its cells, budgets, pairs
    "runs/study_table.py": ("tests/test_study_table.py", "tests/test_late_gain.py"),
    # the gain in the last third and the declared flattening rule it decides
    "runs/learning.py": ("tests/test_late_gain.py", "tests/test_study_table.py"),
    # the height-only ablation of issue #45: its answer rests on this fitness
    "tasks/height_only.py": ("tests/test_height_only.py",),
    # quality diversity (issue #46): descriptors, the archive, the optimizers
    "tasks/descriptors.py": ("tests/test_descriptors.py", "tests/test_qd.py"),
    "evo/archive.py": ("tests/test_archive.py",),
    "evo/qd.py": ("tests/test_qd_params.py",),
    "evo/map_elites.py": ("tests/test_qd_params.py",),
    "evo/cma_me.py": ("tests/test_qd_params.py",),
    "tasks/repertoire.py": ("tests/test_repertoire.py",),
    # the ground's height on debris, which every debris fitness subtracts
    "sim/debris.py": ("tests/test_rubble.py",),
    # the jumps, falls and heights every results table counts
    "sim/analysis.py": ("tests/test_analysis.py",),
    # a repertoire's file: written without pickle, read back only as written
    "rundir/archive.py": ("tests/test_archive_file.py",),
    # how long a study has left, as its processes take its runs
    "runs/study_plan.py": ("tests/test_study_forecast.py",),
    # which comparison a study's figure draws on which row
    "present/study_figure.py": ("tests/test_study_figure.py",),
}

#: modules of which only some functions are mutated (mutmut's name patterns):
#: a task's fitness, not its episode set-up or its report
FUNCTIONS: dict[str, tuple[str, ...]] = {
    "tasks/kick.py": (
        "locustjump.tasks.kick.x_kick_fitness__mutmut_*",
        "locustjump.tasks.kick.x_takeoff__mutmut_*",
        "locustjump.tasks.kick.xǁKickRewardǁ*",
        "locustjump.tasks.kick.xǁKickǁepisode_fitness__mutmut_*",
        "locustjump.tasks.kick.x_kick_descriptors__mutmut_*",
        "locustjump.tasks.kick.xǁKickǁepisode_descriptors__mutmut_*",
    ),
    "tasks/getup.py": (
        "locustjump.tasks.getup.x_up_z__mutmut_*",
        "locustjump.tasks.getup.x_getup_summary__mutmut_*",
        "locustjump.tasks.getup.xǁUpRewardǁ*",
        "locustjump.tasks.getup.xǁGetUpǁepisode_fitness__mutmut_*",
    ),
    "tasks/return_legs.py": (
        "locustjump.tasks.return_legs.x_joint_errors__mutmut_*",
        "locustjump.tasks.return_legs.xǁLegsRewardǁ*",
        "locustjump.tasks.return_legs.xǁReturnLegsǁepisode_fitness__mutmut_*",
    ),
    "tasks/base.py": (
        "locustjump.tasks.base.xǁBehaviourǁfitness__mutmut_*",
        "locustjump.tasks.base.xǁBehaviourǁfitness_terms__mutmut_*",
    ),
    "tasks/composed.py": (
        "locustjump.tasks.composed.x_successive_fitness__mutmut_*",
        "locustjump.tasks.composed.x_successive_terms__mutmut_*",
        "locustjump.tasks.composed.x_overturns__mutmut_*",
        "locustjump.tasks.composed.xǁHeightRewardǁ*",
    ),
    # the forecast (the rest reads files and measures this machine)
    "runs/study_plan.py": ("locustjump.runs.study_plan.x_forecast__mutmut_*",),
    # what is drawn where, not how it looks (sizes, colours, fonts)
    "present/study_figure.py": tuple(
        f"locustjump.present.study_figure.x_{f}__mutmut_*"
        for f in ("resolution_label", "_resolutions", "shift_rows")
    ),
    # the ground's height (the rest is the scene's MJCF, checked by physics)
    "sim/debris.py": ("locustjump.sim.debris.xǁDebrisǁheights__mutmut_*",),
    # the table from its rows, not the scoring and file work around it
    "runs/study_table.py": tuple(
        f"locustjump.runs.study_table.x_{f}__mutmut_*"
        for f in (
            "make_table",
            "_compared",
            "_med",
            "_seeds_text",
            "pairs",
            "_budget_note",
            "_reading",
            "_fmt",
            "_label",
            "_mean",
            "_max",
        )
    ),  # fmt: skip
}

#: what the table leaves out, and why (docs/mutation.md)
NOT_COVERED = """\
`sim/kernels.py` (with `sim/cephes.py`) is not in the table: every
kernel is compiled by Numba (`@njit`), and mutmut 3 does not mutate a
decorated function (it would have to wrap it in a Python trampoline,
which Numba cannot compile). Mutating the kernels needs a tool that
rewrites the file on disk for each mutant (cosmic-ray) and a test run
that cannot reuse compiled code: the kernels' tests
(`tests/test_engine.py`, `tests/test_incallback.py`: 19 tests when this was
measured, 22 now) pass with
`NUMBA_DISABLE_JIT=1` in 86 s, against 323 s from an empty cache
(compiling) and 30 s warm (measured 2026-11-25 on the busy 2-core VM),
so 1.5 to 5 minutes a mutant. No cached machine code can stand in for a
mutant of the modules above: Numba 0.68 keys a kernel's cache on a
SHA-256 of the kernel's own file, `kernels.py` reads no global from
another locustjump module but `cephes.py`'s functions, whose SHA-256 it
carries (`tests/test_incallback.py` checks both), the modules above are
plain NumPy, and each run starts with an empty Numba cache
(`NUMBA_CACHE_DIR`) and a fresh copy of the package under `mutants/src`.
"""

#: mutmut's exit codes: a test failed (or the mutant hung: a timeout)
_KILLED = {1, 3, -24, 24, 152, 255, 36, -11, -9}


def scratch(module: str) -> Path:
    return SCRATCH / module.removesuffix(".py").replace("/", ".")


def source_digest(module: str) -> str:
    return hashlib.sha256((ROOT / "src/locustjump" / module).read_bytes()).hexdigest()


def prepare(module: str, fresh: bool) -> Path:
    """The module's scratch directory (emptied first if ``fresh``)."""
    wd = scratch(module)
    if fresh and wd.exists():
        shutil.rmtree(wd)
    wd.mkdir(parents=True, exist_ok=True)
    for name in ("src", "tests", "scripts"):  # a test may load a script
        if not (wd / name).exists():
            (wd / name).symlink_to(ROOT / name)
    tests = ", ".join(json.dumps(t) for t in MODULES[module])
    (wd / "pyproject.toml").write_text(
        (ROOT / "pyproject.toml").read_text()
        + "\n[tool.mutmut]\n"
        + 'source_paths = ["src"]\n'
        + 'also_copy = ["scripts"]\n'
        + f'only_mutate = ["src/locustjump/{module}"]\n'
        + 'pytest_add_cli_args = ["-p", "no:cacheprovider"]\n'
        + f"pytest_add_cli_args_test_selection = [{tests}]\n"
    )
    return wd


def meta(module: str) -> dict[str, int | None]:
    """Exit code of every mutant of ``module`` that has run."""
    path = scratch(module) / "mutants/src/locustjump" / (module + ".meta")
    if not path.is_file():
        return {}
    codes = json.loads(path.read_text())["exit_code_by_key"]
    codes = {k: v for k, v in codes.items() if v is not None}  # not run (yet)
    patterns = FUNCTIONS.get(module)
    if patterns:
        codes = {k: v for k, v in codes.items() if any(fnmatch(k, p) for p in patterns)}
    return codes


def mutated_line(module: str, name: str) -> str:
    """The lines the mutant changes, as ``- old | + new``."""
    from mutmut.configuration import reset_config
    from mutmut.mutation.diff_apply import get_diff_for_mutant

    cwd = os.getcwd()
    os.chdir(scratch(module))
    try:
        reset_config()
        diff = get_diff_for_mutant(name, path=f"src/locustjump/{module}")
    finally:
        os.chdir(cwd)
    changed = [
        ln[0] + " " + ln[1:].strip()
        for ln in diff.splitlines()
        if ln[:1] in "+-" and not ln.startswith(("+++", "---"))
    ]
    return " | ".join(changed)


def run(module: str, max_children: int, survivors: bool) -> float:
    """Run mutmut on ``module``; its wall time in seconds."""
    digest_file = scratch(module) / "source.sha256"
    same = digest_file.is_file() and digest_file.read_text() == source_digest(module)
    names = list(FUNCTIONS.get(module, ()))
    if survivors and same:
        names = [k for k, v in meta(module).items() if v not in _KILLED]
    wd = prepare(module, fresh=not (survivors and same))
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["NUMBA_CACHE_DIR"] = str(wd / "numba-cache")
    start = time.monotonic()
    with open(wd / "mutmut.log", "w") as log:
        rc = subprocess.call(
            [str(BIN / "mutmut"), "run", "--max-children", str(max_children), *names],
            cwd=wd,
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    wall = time.monotonic() - start
    if rc != 0:
        sys.exit(f"mutmut failed on {module} (exit {rc}): see {wd / 'mutmut.log'}")
    digest_file.write_text(source_digest(module))
    again = survivors and same
    previous = float((wd / "wall.txt").read_text()) if again else 0.0
    (wd / "wall.txt").write_text(f"{previous + wall:.0f}")
    return wall


def listed(name: str, line: str) -> str | None:
    """Why mutant ``name`` (its mutated line ``line``) is equivalent, if
    :data:`EQUIVALENT` lists it: an entry of the same function whose mutated
    text the line holds (mutmut numbers a function's mutants in order, so a
    change to the function may move the number, not the text). The text is
    looked for in what the mutant writes (after ``+``), or in what it
    removes where it writes nothing, so that an entry for one change of a
    line excuses no other change of it."""
    function = name.rpartition("__mutmut_")[0]
    _, plus, written = line.partition(" | + ")
    changed = plus.lstrip(" |") + written if plus else line
    for entry, (text, why) in EQUIVALENT.items():
        if entry.rpartition("__mutmut_")[0] == function and text in changed:
            return why
    return None


class Summary(TypedDict):
    """A module's results: counts, the equivalent ``(name, line, why)`` and
    surviving ``(name, line)`` mutants, and mutmut's wall time (s)."""

    mutants: int
    killed: int
    equivalent: list[tuple[str, str, str]]
    survived: list[tuple[str, str]]
    wall: float


def summary(module: str) -> Summary | None:
    codes = meta(module)
    if not codes:
        return None
    killed = [k for k, v in codes.items() if v in _KILLED]
    equivalent, survived = [], []
    for name in sorted(set(codes) - set(killed)):
        line = mutated_line(module, name)
        why = listed(name, line)
        if why is None:
            survived.append((name, line))
        else:
            equivalent.append((name, line, why))
    wall = scratch(module) / "wall.txt"
    return {
        "mutants": len(codes),
        "killed": len(killed),
        "equivalent": equivalent,
        "survived": survived,
        "wall": float(wall.read_text()) if wall.is_file() else float("nan"),
    }


#: what the functions of :data:`FUNCTIONS` are, in the table
PART = {
    "runs/study_table.py": "the table",
    "runs/study_plan.py": "the forecast",
    "present/study_figure.py": "its rows",
    "sim/debris.py": "the ground's height",
    "tasks/kick.py": "fitness, descriptors",
    "tasks/composed.py": "fitness, falls and recoveries",
}


def label(module: str) -> str:
    if module not in FUNCTIONS:
        return module
    return f"{module} ({PART.get(module, 'fitness')})"


def write_doc(results: dict[str, Summary | None]) -> None:
    rows, details = [], []
    total = {"mutants": 0, "killed": 0, "eq": 0, "sv": 0, "wall": 0.0}
    for module, s in results.items():
        if s is None:
            rows.append(f"| {label(module)} | not run | | | | | |")
            continue
        eq, sv = len(s["equivalent"]), len(s["survived"])
        rate = s["killed"] / max(s["mutants"] - eq, 1)
        rows.append(
            f"| {label(module)} | {s['mutants']} | {s['killed']} | {eq} | {sv} | "
            f"{100 * rate:.1f} % | {s['wall'] / 60:.1f} |"
        )
        for k, v in zip(
            total, (s["mutants"], s["killed"], eq, sv, s["wall"]), strict=True
        ):
            total[k] += v
        for name, line, why in s["equivalent"]:
            details.append(f"- equivalent `{name}`: `{line}` — {why}")
        for name, line in s["survived"]:
            details.append(f"- **survived** `{name}`: `{line}`")
    last_run = (
        f"Every module from scratch (`python scripts/mutation.py`): "
        f"{LAST_RUN.read_text().strip()}.\n"
        if LAST_RUN.is_file()
        else ""
    )
    rate = total["killed"] / max(total["mutants"] - total["eq"], 1)
    rows.append(
        f"| all | {total['mutants']} | {total['killed']} | {total['eq']} | "
        f"{total['sv']} | {100 * rate:.1f} % | {total['wall'] / 60:.1f} |"
    )
    DOC.write_text(
        "# Mutation testing\n\n"
        "Written by `python scripts/mutation.py` (`make mutation`; its docstring\n"
        "says how). mutmut 3 changes one token at a time in each module and\n"
        "runs the tests, among the module's focused test files, that reach\n"
        "the mutated function. Killed: a test failed (or the mutant hung).\n"
        "Rate: killed / (mutants - equivalent). Minutes: mutmut's wall time\n"
        "for the module, one child process, on the project's 2-core VM shared\n"
        "with other work (so slower than on an idle one); a rerun of the\n"
        "survivors (`--survivors`, after tests were added) adds its own.\n"
        + last_run
        + "\n"
        "| module | mutants | killed | equivalent | survived | rate | minutes |\n"
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n"
        + "\n".join(rows)
        + "\n\n"
        + NOT_COVERED
        + "\n## Equivalent and surviving mutants\n\n"
        "Equivalent: no test can tell the mutant from the original (the reason\n"
        "says why). `scripts/mutation.py` matches each listed mutant by its\n"
        "function and its mutated text, not its number alone.\n\n"
        + ("\n".join(details) if details else "None.")
        + "\n"
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("modules", nargs="*", help="default: all of MODULES")
    ap.add_argument("--max-children", type=int, default=1)
    ap.add_argument(
        "--survivors",
        action="store_true",
        help="rerun only the mutants not killed (if the module is unchanged)",
    )
    ap.add_argument("--no-run", action="store_true", help="only write the doc")
    args = ap.parse_args(argv)
    for m in args.modules:
        if m not in MODULES:
            ap.error(f"unknown module {m!r}; choose from {', '.join(MODULES)}")
    start = time.monotonic()
    for module in args.modules or list(MODULES):
        if not args.no_run:
            wall = run(module, args.max_children, args.survivors)
            print(f"{module}: mutmut ran {wall / 60:.1f} min")
    results = {m: summary(m) for m in MODULES}
    if not (args.modules or args.survivors or args.no_run):
        minutes = (time.monotonic() - start) / 60
        mutants = sum(r["mutants"] for r in results.values() if r)
        LAST_RUN.write_text(
            f"{minutes:.1f} min for its {len(MODULES)} modules then "
            f"({mutants:,} mutants), {time.strftime('%Y-%m-%d')}"
        )
    write_doc(results)
    for module, s in results.items():
        if s is not None:
            for name, line in s["survived"]:
                print(f"{module}: survived {name}: {line}")
    print(f"wrote {DOC.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
