"""The kick's presentation (paper §3.1, Fig. 7): the evolved kick beside the
rule-based jumping, and the claim "about 2x as high"."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from locustjump.present.plots import trajectory_figure
from locustjump.present.stages.base import Claim, Episodes, Reporter, fmt, yes
from locustjump.rundir.layout import EVAL
from locustjump.sim.analysis import find_jumps, ground_profile

FIGURE = "kick_vs_rules.png"  # Fig. 7
#: The paper (Fig. 7): the evolved kick jumps about 2x as high as the rule.
PAPER_KICK_RATIO = 2.0
#: What we count as "about 2x" (stated in results.md).
KICK_RATIO_OK = 1.8
#: Why "2x" fails, as measured by the ceiling study (docs/science.md).
KICK_WHY = (
    "no controller found rises more than 1.27x as high as the rule's first "
    "jump (1.24x at 12 substeps) — CMA-ES and the RCGA maximising the apex "
    "itself, with the network or open-loop (studies/kick-ceiling.toml, "
    "docs/science.md): our rule already reaches 79 % of the creature's "
    "ceiling, so 2x is not physically possible against it; a rule kicking at "
    "6 deg/step or slower would make it true"
)


class KickReporter(Reporter):
    figures = ((f"{EVAL}/{FIGURE}", "kick", "Kick vs rule-based (Fig. 7):"),)
    headline = ("apex_height_m", "apex_height_ratio_to_rules")

    def write_figures(self, ep: Episodes, out: Path) -> list[Path]:
        """``kick_vs_rules.png``: the paper's Fig. 7, evolved kick beside the
        rule-based jumping over the same episode length (alone, for a
        behaviour that compares with none)."""
        beh, res, p, reference = ep
        qpos = res["qpos"][0]
        reference = reference or beh.reference(p)
        curves = [("evolved kick", qpos, find_jumps(qpos, p, beh.scene))]
        vs = ""
        if reference is not None:
            rules = reference.head(beh.n_steps, p)
            curves.append(("rule-based", rules.qpos, rules.jumps))
            vs = " vs rule-based"
        path = out / FIGURE
        trajectory_figure(
            path,
            curves,
            title=f"Kicking the ground: evolved{vs} ({beh.n_steps} steps)",
            ground=ground_profile(qpos, p, beh.scene),
        )
        return [path]

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        claim = Claim(
            "the evolved kick jumps about 2x as high as the rule-based first jump "
            "(Fig. 7)",
            f"~{PAPER_KICK_RATIO:g}x",
        )
        if record is None:
            return [claim]
        k = record["metrics"]
        ratio = k.get("apex_height_ratio_to_rules")
        ok = ratio is not None and ratio >= KICK_RATIO_OK
        return [
            Claim(
                claim.text,
                claim.paper,
                f"{fmt(ratio, unit='x')} ({fmt(k['apex_height_m'], unit=' m')} vs "
                f"{fmt(k.get('rules_first_apex_height_m'), unit=' m')})",
                f"{yes(ok)} (>= {KICK_RATIO_OK}x)",
                ratio,
                ok,
                "apex / rule-based first apex (x)",
                why=KICK_WHY,
                reason=_reason(k),
            )
        ]


def _reason(k: dict[str, Any]) -> str:
    """What this kick did instead of jumping 2x as high."""
    parts = [f"its highest point is {k['apex_height_m']:.2f} m"]
    if k.get("distance_at_apex_m") is not None:
        parts.append(f"{k['distance_at_apex_m']:.2f} m forward")
    if k.get("takeoff_angle_deg") is not None:
        parts.append(f"after a take-off at {k['takeoff_angle_deg']:.0f} deg")
    return ", ".join(parts) + ": E = max dx*dz rewards distance as much as height"


class CeilingReporter(KickReporter):
    """The kick's ceiling behaviours (beyond the paper): the kick's figure,
    no claim of the paper."""

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        return []
