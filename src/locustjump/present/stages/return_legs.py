"""Returning the legs' presentation (paper §3.3, Fig. 10)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from locustjump.present.plots import joint_angles_figure
from locustjump.present.stages.base import Claim, Episodes, Reporter, yes
from locustjump.rundir.layout import EVAL

FIGURE = "return_legs.png"  # Fig. 10
#: What we count as "the legs return to phi" (stated in results.md).
LEGS_ERROR_OK_DEG = 5.0
#: What other shipped runs show: at 60 generations, seed and engine decide
#: (tests/test_results_text.py re-reads each run it cites)
RETURN_LEGS_WHY = (
    "at 60 generations the seed and the engine decide: seeds 1 and 2 on the "
    "compiled engine (results/study/long-return-legs-rcga-s1, -s2) and seed 0 "
    "on the NumPy engine (results/long-seed0) end with every joint within "
    "4.95 deg, as seed 0 does at 1000 generations (results/paper-seed0), the "
    "knees at their range limit 4.9 deg short of phi; seed 0 on the compiled "
    "engine (results/demo-seed0), whose controllers differ from NumPy's by a "
    "few ulp a step and so evolve other genomes, ends with hip_r 39.76 deg off"
)


class ReturnLegsReporter(Reporter):
    figures = ((f"{EVAL}/{FIGURE}", "return-legs", "Returning the legs (Fig. 10):"),)
    headline = ("final_error_deg",)

    def write_figures(self, ep: Episodes, out: Path) -> list[Path]:
        """``return_legs.png``: the paper's Fig. 10, the joint angles over time
        converging to phi."""
        beh, res, p, backend = ep
        path = out / FIGURE
        joint_angles_figure(path, res["obs"][0, :, 0:4], p.ready_angles())
        return [path]

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        claim = Claim("the legs return to the ready posture (Fig. 10)", "yes")
        if record is None:
            return [claim]
        final = record["metrics"]["final_error_deg"]
        err = max(final.values())
        return [
            Claim(
                claim.text,
                claim.paper,
                f"largest final error {err:.2f} deg",
                f"{yes(err <= LEGS_ERROR_OK_DEG)} (every joint within "
                f"{LEGS_ERROR_OK_DEG:g} deg)",
                err,
                err <= LEGS_ERROR_OK_DEG,
                "largest final joint error (deg)",
                why=RETURN_LEGS_WHY,
                reason=_reason(final, record["metrics"].get("start_error_deg", {})),
            )
        ]


def _reason(final: dict[str, float], start: dict[str, float]) -> str:
    """Which joints end outside the criterion, and whether they moved away."""
    off = sorted((j for j in final if final[j] > LEGS_ERROR_OK_DEG),
                 key=lambda j: -final[j])  # fmt: skip
    parts = []
    for joint in off:
        s = start.get(joint)
        moved = "" if s is None or final[joint] <= s else " (it moved away)"
        since = "" if s is None else f", from {s:.2f} deg at the start{moved}"
        parts.append(f"{joint} ends {final[joint]:.2f} deg from phi{since}")
    rest = [j for j in final if j not in off]
    if rest:
        worst = max(final[j] for j in rest)
        verb = "ends" if len(rest) == 1 else "end"
        parts.append(f"{', '.join(rest)} {verb} within {worst:.2f} deg")
    return (
        "; ".join(parts)
        + f": the network has not learnt to bring {' and '.join(off)} back"
    )
