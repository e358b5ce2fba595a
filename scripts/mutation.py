"""Mutation testing of the core modules (issue #48), with mutmut 3.

For each module of :data:`MODULES` (``scripts/mutation_targets.py``),
mutmut changes one token at a time (a comparison, an operator, a constant,
a string, an argument) and runs the tests that reach the mutated function
(mutmut's per-function selection, measured once per module by a "stats"
run) from the module's *focused* test files only, never
the whole suite. A mutant no test notices is a behaviour no test states.

Each module runs in its own scratch directory ``.mutation/<module>/``
(``src``, ``tests``, ``scripts`` and ``results`` linked, ``pyproject.toml``
with the module's ``[tool.mutmut]``; mutmut copies and mutates under
``mutants/`` there).
Numba's cache goes to a directory of that scratch run (``NUMBA_CACHE_DIR``),
so compiled code cached from the checkout is never run in place of a mutant.

``docs/mutation.md`` is written from the results of every module that has
run on this machine (its scratch directory holds them); a module that has
not keeps its row and its mutants from the page as it stands. Per module:
mutants, killed (a test failed; timeouts count), equivalent (listed in
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
import re
import shutil
import subprocess
import sys
import time
from fnmatch import fnmatch
from pathlib import Path
from typing import TypedDict

from mutation_equivalent import EQUIVALENT
from mutation_targets import FUNCTIONS, MODULES, NO_OPENGL, NOT_COVERED, PART

ROOT = Path(__file__).resolve().parent.parent
SCRATCH = ROOT / ".mutation"
DOC = ROOT / "docs" / "mutation.md"
#: the wall time and date of the last run of every module from scratch
LAST_RUN = SCRATCH / "last-run.txt"
BIN = Path(sys.executable).parent

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
    # a test may load a script, or read a shipped run
    for name in ("src", "tests", "scripts", "results"):
        if not (wd / name).exists():
            (wd / name).symlink_to(ROOT / name)
    tests = ", ".join(json.dumps(t) for t in MODULES[module])
    (wd / "pyproject.toml").write_text(
        (ROOT / "pyproject.toml").read_text()
        + "\n[tool.mutmut]\n"
        + 'source_paths = ["src"]\n'
        + 'also_copy = ["scripts", "results"]\n'
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
    if module in NO_OPENGL:
        env["MUJOCO_GL"] = "disable"
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
    line excuses no other change of it; or the whole line, for a change that
    writes what many others do (an argument dropped before a closing ``)``)."""
    function = name.rpartition("__mutmut_")[0]
    _, plus, written = line.partition(" | + ")
    changed = plus.lstrip(" |") + written if plus else line
    for entry, (text, why) in EQUIVALENT.items():
        if entry.rpartition("__mutmut_")[0] == function and (
            text in changed or text == line
        ):
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


def label(module: str) -> str:
    if module not in FUNCTIONS:
        return module
    return f"{module} ({PART.get(module, 'fitness')})"


def dotted(module: str) -> str:
    """``module``'s name as mutmut's mutant names begin: ``locustjump.evo.rcga``
    (a package's ``__init__.py`` is the package)."""
    return "locustjump." + module.removesuffix(".py").removesuffix("/__init__").replace(
        "/", "."
    )


def module_of(mutant: str) -> str | None:
    """The module of :data:`MODULES` a mutant's name (``<module>.x_...`` or
    ``<module>.xǁClassǁ...``) belongs to."""
    prefix = re.split(r"\.xǁ|\.x_", mutant, maxsplit=1)[0]
    return next((m for m in MODULES if dotted(m) == prefix), None)


class Kept(TypedDict):
    """A module's row of the page as last written: its counts (mutants,
    killed, equivalent, survived), its minutes and its lines of mutants."""

    counts: list[int]
    minutes: float
    details: list[str]


def previous_doc() -> tuple[dict[str, Kept], str]:
    """The rows of ``docs/mutation.md`` as it stands, by module, and its line
    on the last run of every module: what a module not run on this machine
    (whose scratch results are not here) keeps."""
    if not DOC.is_file():
        return {}, ""
    text = DOC.read_text()
    by_label = {label(m): m for m in MODULES}
    kept: dict[str, Kept] = {}
    for row in re.findall(r"^\| (.+?) \| (\d+) \| (\d+) \| (\d+) \| (\d+) \| "
                          r"[\d.]+ % \| ([\d.]+|nan) \|$", text, re.M):  # fmt: skip
        if row[0] in by_label:
            kept[by_label[row[0]]] = {
                "counts": [int(c) for c in row[1:5]],
                "minutes": float(row[5]),
                "details": [],
            }
    for line in text.splitlines():
        found = re.match(r"^- (?:equivalent|\*\*survived\*\*) `([^`]+)`", line)
        module = module_of(found.group(1)) if found else None
        if module in kept:
            kept[module]["details"].append(line)
    last = re.search(r"^Every module from scratch .*$", text, re.M)
    return kept, last.group(0) + "\n" if last else ""


def not_mutated() -> str:
    """The package's modules outside the table: what no mutant has checked
    yet (a paragraph of the page; names only, so that the page changes when
    a module is added or mutated, not whenever one is edited)."""
    src = ROOT / "src" / "locustjump"
    every = sorted(str(f.relative_to(src)) for f in src.rglob("*.py"))
    left = [m for m in every if m not in MODULES]
    return (
        f"Not in the table: {len(left)} of the package's {len(every)} modules, "
        + ", ".join(f"`{m}`" for m in left)
        + ".\n"
    )


def write_doc(results: dict[str, Summary | None]) -> None:
    """``docs/mutation.md`` from ``results``; a module without results here
    keeps its row and its mutants from the page as it stands."""
    kept, last_line = previous_doc()
    rows, details = [], []
    total = {"mutants": 0, "killed": 0, "eq": 0, "sv": 0, "wall": 0.0}
    for module, s in results.items():
        if s is None and module not in kept:
            rows.append(f"| {label(module)} | not run | | | | | |")
            continue
        if s is None:
            mutants, killed, eq, sv = kept[module]["counts"]
            wall = kept[module]["minutes"] * 60
            details.extend(kept[module]["details"])
        else:
            mutants, killed, wall = s["mutants"], s["killed"], s["wall"]
            eq, sv = len(s["equivalent"]), len(s["survived"])
            for name, line, why in s["equivalent"]:
                details.append(f"- equivalent `{name}`: `{line}` — {why}")
            for name, line in s["survived"]:
                details.append(f"- **survived** `{name}`: `{line}`")
        rate = killed / max(mutants - eq, 1)
        rows.append(
            f"| {label(module)} | {mutants} | {killed} | {eq} | {sv} | "
            f"{100 * rate:.1f} % | {wall / 60:.1f} |"
        )
        # the total of the minutes shown (a kept row holds no more than those)
        shown = round(wall / 60, 1) * 60
        for k, v in zip(total, (mutants, killed, eq, sv, shown), strict=True):
            total[k] += v
    last_run = (
        f"Every module from scratch (`python scripts/mutation.py`): "
        f"{LAST_RUN.read_text().strip()}.\n"
        if LAST_RUN.is_file()
        else last_line
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
        "survivors (`--survivors`, after tests were added) adds its own. A\n"
        "module not run on the machine that last wrote this page keeps its row\n"
        "and its mutants below from the page before.\n" + last_run + "\n"
        "| module | mutants | killed | equivalent | survived | rate | minutes |\n"
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n"
        + "\n".join(rows)
        + "\n\n"
        + NOT_COVERED
        + "\n"
        + not_mutated()
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
