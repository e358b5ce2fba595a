"""Mutation testing of the core modules (issue #48), with mutmut 3.

For each module below, mutmut changes one token at a time (a comparison, an
operator, a constant, a string, an argument) and runs the tests that reach
the mutated function (mutmut's per-function selection, measured once per
module by a "stats" run) from the module's *focused* test files only, never
the whole suite. A mutant no test notices is a behaviour no test states.

Each module runs in its own scratch directory ``.mutation/<module>/``
(``src`` and ``tests`` linked, ``pyproject.toml`` with the module's
``[tool.mutmut]``; mutmut copies and mutates under ``mutants/`` there).
Numba's cache goes to a directory of that scratch run (``NUMBA_CACHE_DIR``),
so compiled code cached from the checkout is never run in place of a mutant.

``docs/mutation.md`` is written from the results of every module that has
run: mutants, killed (a test failed; timeouts count), equivalent (listed in
:data:`EQUIVALENT` with the reason, checked against the mutant's diff),
survived (no test failed, or no test reached it) and the kill rate
``killed / (mutants - equivalent)``.

    python scripts/mutation.py                  # every module (hours on 2 cores)
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
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCRATCH = ROOT / ".mutation"
DOC = ROOT / "docs" / "mutation.md"
BIN = Path(sys.executable).parent

#: module (under src/locustjump) -> the focused test files that state it
MODULES: dict[str, tuple[str, ...]] = {
    "evo/rcga.py": (
        "tests/test_rcga.py",
        "tests/test_rcga_behaviour.py",
        "tests/test_optimizers.py",
    ),
    "rundir/metrics.py": (
        "tests/test_metrics_contract.py",
        "tests/test_runs.py",
        "tests/test_optimizers.py",
    ),
    "rundir/config.py": (
        "tests/test_config_contract.py",
        "tests/test_migrations.py",
        "tests/test_runs.py",
    ),
    "sim/sensors.py": ("tests/test_sensors_controller.py",),
    "sim/actuation.py": ("tests/test_sensors_controller.py", "tests/test_engine.py"),
    "rundir/checkpoint.py": (
        "tests/test_checkpoint_contract.py",
        "tests/test_hardening.py",
        "tests/test_runs.py",
    ),
}

#: mutant name -> (its mutated line, as mutmut's diff shows it, without
#: indentation; why no test can tell it from the original)
EQUIVALENT: dict[str, tuple[str, str]] = {}

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
    for name in ("src", "tests"):
        if not (wd / name).exists():
            (wd / name).symlink_to(ROOT / name)
    tests = ", ".join(json.dumps(t) for t in MODULES[module])
    (wd / "pyproject.toml").write_text(
        (ROOT / "pyproject.toml").read_text()
        + "\n[tool.mutmut]\n"
        + 'source_paths = ["src"]\n'
        + f'only_mutate = ["src/locustjump/{module}"]\n'
        + 'pytest_add_cli_args = ["-p", "no:cacheprovider"]\n'
        + f"pytest_add_cli_args_test_selection = [{tests}]\n"
    )
    return wd


def meta(module: str) -> dict[str, int | None]:
    """Exit code of every mutant of ``module`` (None: not run)."""
    path = scratch(module) / "mutants/src/locustjump" / (module + ".meta")
    if not path.is_file():
        return {}
    return json.loads(path.read_text())["exit_code_by_key"]


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
    names: list[str] = []
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
    previous = float((wd / "wall.txt").read_text()) if names else 0.0
    (wd / "wall.txt").write_text(f"{previous + wall:.0f}")
    return wall


def summary(module: str) -> dict | None:
    codes = meta(module)
    if not codes:
        return None
    killed = [k for k, v in codes.items() if v in _KILLED]
    equivalent, survived, stale = [], [], []
    for name in sorted(set(codes) - set(killed)):
        line = mutated_line(module, name)
        if name in EQUIVALENT:
            expected, why = EQUIVALENT[name]
            if expected not in line:  # renumbered: the list must follow
                stale.append((name, line, expected))
            else:
                equivalent.append((name, line, why))
        else:
            survived.append((name, line))
    wall = scratch(module) / "wall.txt"
    return {
        "mutants": len(codes),
        "killed": len(killed),
        "equivalent": equivalent,
        "survived": survived,
        "stale": stale,
        "wall": float(wall.read_text()) if wall.is_file() else float("nan"),
    }


def write_doc(results: dict[str, dict | None]) -> None:
    rows, details = [], []
    for module, s in results.items():
        if s is None:
            rows.append(f"| {module} | not run | | | | | |")
            continue
        eq, sv = len(s["equivalent"]), len(s["survived"]) + len(s["stale"])
        rate = s["killed"] / max(s["mutants"] - eq, 1)
        rows.append(
            f"| {module} | {s['mutants']} | {s['killed']} | {eq} | {sv} | "
            f"{100 * rate:.1f} % | {s['wall'] / 60:.1f} |"
        )
        for name, line, why in s["equivalent"]:
            details.append(f"- equivalent `{name}`: `{line}` — {why}")
        for name, line in s["survived"]:
            details.append(f"- **survived** `{name}`: `{line}`")
        for name, line, expected in s["stale"]:
            details.append(
                f"- **listed as equivalent but now** `{name}`: `{line}` "
                f"(listed: `{expected}`)"
            )
    DOC.write_text(
        "# Mutation testing\n\n"
        "Written by `python scripts/mutation.py` (`make mutation`), which says\n"
        "how (its docstring): mutmut 3 changes one token at a time in each\n"
        "module and runs the module's focused tests that reach the mutated\n"
        "function. Rate: killed / (mutants - equivalent). Minutes: the wall\n"
        "time of mutmut on that module, one child process, on the 2-core VM\n"
        "shared with other work.\n\n"
        "| module | mutants | killed | equivalent | survived | rate | minutes |\n"
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n"
        + "\n".join(rows)
        + "\n\n## Equivalent and surviving mutants\n\n"
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
    for module in args.modules or list(MODULES):
        if not args.no_run:
            wall = run(module, args.max_children, args.survivors)
            print(f"{module}: mutmut ran {wall / 60:.1f} min")
    results = {m: summary(m) for m in MODULES}
    write_doc(results)
    for module, s in results.items():
        if s is not None:
            for name, line in s["survived"]:
                print(f"{module}: survived {name}: {line}")
    print(f"wrote {DOC.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
