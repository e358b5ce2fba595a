"""Would pairing by seed narrow a study's intervals? (exploratory)

A study's arms share each seed's training terrains, so their scores could be
compared seed by seed (paired) instead of as two independent samples, as the
study's table does. Pairing narrows an interval only where the two arms'
scores go up and down together over seeds. For each comparison of a study's
table (``table.json``, as ``locustjump study FILE --table`` writes it) and
each scoring resolution, this prints the seeds both arms ran, Pearson's r
of their scores over those seeds with its 95 % interval (SciPy's, by
Fisher's z) and Spearman's rho, and the ratio ``sd(a - b) / sqrt(var(a) +
var(b))``: the width of a paired interval relative to an unpaired one, to
first order (1 at r = 0, below 1 where r > 0).

    .venv/bin/python scripts/study_pairing.py results/studies/debris-composition-5seeds

Exploratory: the study declared an unpaired analysis before its runs
finished; this says whether another one would have been sharper, not what
the answer is.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from locustjump import rundir
from locustjump.present.ranktests import scipy_stats
from locustjump.runs.study_table import TABLE_JSON


def paired_scores(
    table: dict[str, Any], a: str, b: str, at: str
) -> tuple[list[int], np.ndarray, np.ndarray]:
    """The seeds on which arms ``a`` and ``b`` (names) both have a score at
    resolution ``at``, and their two score arrays in seed order."""
    by: dict[str, dict[int, float]] = {a: {}, b: {}}
    for row in table["runs"]:
        if row["arm"] in by and row["at"].get(at) is not None:
            by[row["arm"]][int(row["seed"])] = float(row["at"][at]["score"])
    seeds = sorted(set(by[a]) & set(by[b]))
    return (seeds, np.array([by[a][s] for s in seeds]),
            np.array([by[b][s] for s in seeds]))  # fmt: skip


def pairing_rows(table: dict[str, Any]) -> list[dict[str, Any]]:
    """A row per comparison of ``table`` and resolution: the pair, the seeds,
    Pearson's r [95 % interval], Spearman's rho, the width ratio."""
    stats = scipy_stats()
    arm_of = {v["label"]: k for k, v in table["arms"].items()}
    rows = []
    for at, pairs in table["pairs"].items():
        for pair in pairs:
            seeds, x, y = paired_scores(table, arm_of[pair["a"]], arm_of[pair["b"]], at)
            row: dict[str, Any] = {"at": at, "a": pair["a"], "b": pair["b"],
                                   "n": len(seeds)}  # fmt: skip
            if len(seeds) >= 3 and x.std() > 0 and y.std() > 0:
                r = stats.pearsonr(x, y)
                ci = r.confidence_interval(0.95)
                row.update(
                    r=float(r.statistic), low=float(ci.low), high=float(ci.high),
                    rho=float(stats.spearmanr(x, y).statistic),
                    ratio=float(np.std(x - y, ddof=1)
                                / math.sqrt(x.var(ddof=1) + y.var(ddof=1))),
                )  # fmt: skip
            rows.append(row)
    return rows


def _g(v: float | None) -> str:
    return "-" if v is None else f"{v:.2f}"


def render(rows: list[dict[str, Any]]) -> str:
    """The rows as a Markdown table."""
    out = [
        "| substeps | pair | seeds | Pearson r [95 % CI] | Spearman rho | "
        "paired / unpaired width |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        at = "as trained" if r["at"] == "None" else r["at"]
        corr = (f"{r['r']:.2f} [{r['low']:.2f}, {r['high']:.2f}]"
                if "r" in r else "- (too few seeds or no spread)")  # fmt: skip
        out.append(f"| {at} | {r['a']} - {r['b']} | {r['n']} | {corr} | "
                   f"{_g(r.get('rho'))} | {_g(r.get('ratio'))} |")  # fmt: skip
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "table", type=Path, help="a study's table.json, or the directory holding it"
    )
    args = ap.parse_args(argv)
    path = args.table / TABLE_JSON if args.table.is_dir() else args.table
    if not path.is_file():
        print(f"study_pairing.py: {path}: no such table (run `locustjump study "
              "FILE --table` first)", file=sys.stderr)  # fmt: skip
        return 2
    print(render(pairing_rows(rundir.read_json(path))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
