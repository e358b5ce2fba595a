"""Successive jumping's presentation (paper §4, Fig. 12): the composed
controller's trajectory with the selected simple behaviour, its claim "every
jump more than 2x", and the monolithic baseline's answer to "does composition
help?", for one seed and across seeds (with a sign test)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from locustjump.present.plots import composed_figure
from locustjump.present.stages.base import Claim, Episodes, Reporter, fmt, yes
from locustjump.rundir.layout import EVAL
from locustjump.sim.analysis import find_jumps, ground_profile
from locustjump.tasks.composed import SIMPLE, Composed
from locustjump.tasks.monolithic import Monolithic

#: The paper (Fig. 12): every composed jump is more than 2x the rule's.
PAPER_COMPOSED_RATIO = 2.0
#: Why it fails, as measured by the ceiling study (docs/science.md).
COMPOSED_WHY = (
    "a take-off from the ready posture rises at most 1.27x as high as the "
    "rule's first jump (the kick's ceiling, docs/science.md), so no composed "
    "jump is 2x the rule's unless it gains height from its landings, which "
    "we saw only on the 3-substep physics (bounces of 3.5-6 m; docs/science.md)"
)


class SuccessiveReporter(Reporter):
    """The figure shared by the composed and the monolithic behaviour."""

    headline: ClassVar[tuple[str, ...]] = ("jumps", "apex_heights_m")

    def write_figures(self, ep: Episodes, out: Path) -> list[Path]:
        """``<name>.png``: the paper's Fig. 12, the trajectory over the
        rule-based one (for a behaviour that compares with one) and, under it,
        which simple behaviour was selected."""
        beh, res, p, reference = ep
        qpos = res["qpos"][0]
        reference = reference or beh.reference(p)
        selected = res["memory"][0, 1:, 0] if "memory" in res.records else None
        path = out / f"{beh.name}.png"
        jumps = find_jumps(qpos, p, beh.scene)
        what = "Successive jumping" if len(jumps) > 1 else _jumps(len(jumps))
        curves = [(beh.name, qpos, jumps)]
        vs = ""
        if reference is not None:
            rules = reference.head(beh.n_steps, p)
            curves.append(("rule-based", rules.qpos, rules.jumps))
            vs = " vs rule-based"
        composed_figure(
            path,
            curves,
            selected,
            beh.memory_labels or SIMPLE,
            title=f"{what}: {beh.name}{vs} ({beh.n_steps} steps)",
            ground=ground_profile(qpos, p, beh.scene),
        )
        return [path]


class ComposedReporter(SuccessiveReporter):
    figures = (
        (
            f"{EVAL}/composed.png",
            "composed",
            "The composed controller beside the rule-based jumping, with the "
            "selected simple behaviour (Fig. 12):",
        ),
    )
    headline = ("jumps", "apex_heights_m", "min_apex_ratio_to_rules")

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        claim = Claim(
            "every composed jump is more than 2x as high as the rule-based jumps "
            "(Fig. 12)",
            f"> {PAPER_COMPOSED_RATIO:g}x at every jump",
        )
        if record is None:
            return [claim]
        c = record["metrics"]
        ratios = c.get("apex_ratios_to_rules", [])
        low = min(ratios) if ratios else None
        ok = c["jumps"] >= 2 and low is not None and low > PAPER_COMPOSED_RATIO
        ratio = (
            "nothing to compare"
            if low is None
            else f"smallest ratio {fmt(low, unit='x')}"
        )
        return [
            Claim(
                claim.text,
                claim.paper,
                f"{_jumps(c['jumps'])}, {ratio} (rule-based mean "
                f"apex {fmt(c.get('rules_mean_apex_height_m'), unit=' m')})",
                f"{yes(ok)} (>= 2 jumps, each > 2x)",
                low,
                ok,
                "smallest jump / rule-based mean apex (x)",
                why=COMPOSED_WHY,
                reason=_composed_reason(c),
            )
        ]


def _jumps(n: int) -> str:
    return f"{n} jump{'s' * (n != 1)}"


def _composed_reason(c: dict[str, Any]) -> str:
    """What this composed controller did: which behaviour the switcher
    selected, and its jumps or why it made none."""
    steps = c.get("selected_steps") or {}
    chosen = [f"{name} {n}" for name, n in steps.items() if n]
    if len(chosen) == 1:  # "return-legs 3000 of the 3000 steps"
        chosen = [f"{chosen[0].rsplit(' ', 1)[0]} for all"]
    elif len(chosen) > 1:
        chosen[-2:] = [f"{chosen[-2]} and {chosen[-1]}"]
    switcher = (
        f" (the switcher selects {', '.join(chosen)} of the "
        f"{sum(steps.values())} steps)"
        if chosen
        else ""
    )
    if c["jumps"] == 0:
        never = [name for name, n in steps.items() if n == 0]
        why = f"; it never selects {' or '.join(never)}" if never else ""
        lying = ", and it ends on its back" if c.get("final_up_z", 1.0) < 0 else ""
        return f"the composed controller never jumps{switcher}{why}{lying}"
    heights = c.get("apex_heights_m") or []
    top = f", the highest {max(heights):.2f} m" if heights else ""
    return f"{_jumps(c['jumps'])}{top}{switcher}"


class MonolithicReporter(SuccessiveReporter):
    figures = ((f"{EVAL}/monolithic.png", "monolithic", "The monolithic baseline:"),)

    def report_section(self, stages: dict[str, dict[str, Any]]) -> list[str]:
        """Does composition help? The composed controller against this one,
        at the same number of genome evaluations."""
        mono_name = Monolithic.name
        lines = ["## Beyond the paper: does composition help?", ""]
        missing = [s for s in (Composed.name, mono_name) if s not in stages]
        if missing:
            return lines + [
                "Needs the composed and the monolithic stages (not run yet: "
                f"{', '.join(missing)}).",
                "",
            ]
        c, mono = stages[Composed.name]["metrics"], stages[mono_name]["metrics"]
        lines += [
            "One 9-10-4 network evolved directly on the composed task (same start, "
            "3000 steps, same fitness E: Eq. 4, on a terrain with its progress "
            "term) with as many genome evaluations as the four stages of the "
            "composed controller together:",
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
            ("monolithic", mono, stages[mono_name]["evaluations"]),
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
            f"On this seed at this budget the composed controller scores "
            f"{'above' if better else 'below'} the monolithic one: its E is {times} "
            "the monolithic one's (one seed: no evidence either way; "
            "docs/science.md compares seeds).",
            "",
        ]

    def across_seeds(self, seeds: dict[int, dict[str, dict[str, Any]]]) -> list[str]:
        """Composed E / monolithic E, seed by seed (same evaluation budget)."""
        mono_name = Monolithic.name
        pairs = {
            s: (st[Composed.name]["fitness"], st[mono_name]["fitness"])
            for s, st in seeds.items()
            if Composed.name in st and mono_name in st
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
            f"seeds; median ratio {fmt(med, unit='x')}; two-sided sign test over the "
            f"seeds p = {sign_test(wins, len(pairs)):.3g}.",
            "",
        ]


def sign_test(wins: int, n: int) -> float:
    """Two-sided exact sign test: the probability of a split at least as
    uneven as ``wins`` of ``n`` if either side wins each pair with odds 1/2."""
    k = min(wins, n - wins)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2.0**n
    return min(1.0, 2.0 * tail)
