"""The monolithic baseline (beyond the paper): one 9-10-4 network evolved
directly on the composed behaviour's episode and fitness (Eq. 4), with as many
genome evaluations as the composed controller's four stages together — does
composition help? Its ``report_section`` and ``across_seeds`` answer that in
``results.md``, for one seed and across seeds (with a sign test).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from locustjump.rundir.layout import EVAL
from locustjump.tasks.base import fmt
from locustjump.tasks.composed import SIMPLE, Composed, _Successive


class Monolithic(_Successive):
    """Beyond the paper: one 9-10-4 network on the composed task."""

    name = "monolithic"
    eval_record = ("qpos", "obs", "ctrl")
    figures = ((f"{EVAL}/monolithic.png", "monolithic", "The monolithic baseline:"),)
    gym_id = "LocustSuccessiveJump-v0"

    def report_section(self, stages: dict[str, dict[str, Any]]) -> list[str]:
        """Does composition help? The composed controller against this one,
        at the same number of genome evaluations."""
        lines = ["## Beyond the paper: does composition help?", ""]
        missing = [s for s in (Composed.name, self.name) if s not in stages]
        if missing:
            return lines + [
                "Needs the composed and the monolithic stages (not run yet: "
                f"{', '.join(missing)}).",
                "",
            ]
        c, mono = stages[Composed.name]["metrics"], stages[self.name]["metrics"]
        lines += [
            "One 9-10-4 network evolved directly on the composed task (same start, "
            "3000 steps, E = sum z) with as many genome evaluations as the four "
            "stages of the composed controller together:",
            "",
            "| controller | fitness E (m x steps) | mean height (m) | jumps | "
            "distance (m) | overturned / recovered | evaluations |",
            "| --- | --- | --- | --- | --- | --- | --- |",
        ]
        composed_evals = sum(
            stages[s]["evaluations"] for s in (*SIMPLE, Composed.name) if s in stages
        )
        for name, m, evals in (
            ("composed (3 frozen + switcher)", c, composed_evals),
            ("monolithic", mono, stages[self.name]["evaluations"]),
        ):
            lines.append(
                f"| {name} | {m['fitness']:.1f} | {m['mean_height_m']:.3f} | "
                f"{m['jumps']} | {m['distance_m']:.2f} | {m['overturned']} / "
                f"{m['recovered']} | {evals:,} |"
            )
        better = c["fitness"] > mono["fitness"]
        times = (
            f"{c['fitness'] / mono['fitness']:.2f}x" if mono["fitness"] > 0 else "n/a"
        )
        return lines + [
            "",
            f"Composition {'helps' if better else 'does not help'} at this budget: "
            f"the composed controller's E is {times} the monolithic one's.",
            "",
        ]

    def across_seeds(self, seeds: dict[int, dict[str, dict[str, Any]]]) -> list[str]:
        """Composed E / monolithic E, seed by seed (same evaluation budget)."""
        pairs = {
            s: (st[Composed.name]["fitness"], st[self.name]["fitness"])
            for s, st in seeds.items()
            if Composed.name in st and self.name in st
        }
        lines = ["## Beyond the paper: does composition help?", ""]
        if not pairs:
            return lines + [
                "No seed has both the composed and the monolithic stage yet.",
                "",
            ]
        ratios = [c / m if m > 0 else float("nan") for c, m in pairs.values()]
        wins = sum(c > m for c, m in pairs.values())
        lines += [
            "| seed | composed E | monolithic E | composed / monolithic |",
            "| --- | --- | --- | --- |",
        ]
        lines += [
            f"| {s} | {c:.1f} | {m:.1f} | {r:.2f}x |"
            for (s, (c, m)), r in zip(pairs.items(), ratios, strict=True)
        ]
        med = float(np.nanmedian(ratios)) if any(r == r for r in ratios) else None
        return lines + [
            "",
            f"Composition beats the monolithic network in {wins} of {len(pairs)} "
            f"seeds; median ratio {fmt(med)}x; two-sided sign test over the "
            f"seeds p = {sign_test(wins, len(pairs)):.3g}.",
            "",
        ]


def sign_test(wins: int, n: int) -> float:
    """Two-sided exact sign test: the probability of a split at least as
    uneven as ``wins`` of ``n`` if either side wins each pair with odds 1/2."""
    k = min(wins, n - wins)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2.0**n
    return min(1.0, 2.0 * tail)


__all__ = ["Monolithic", "sign_test"]
