"""Returning the legs' presentation (paper §3.3, Fig. 10)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from locustjump.present.plots import joint_angles_figure
from locustjump.present.stages.base import Claim, Episodes, Reporter, yes
from locustjump.rundir.layout import EVAL

if TYPE_CHECKING:
    pass

FIGURE = "return_legs.png"  # Fig. 10
#: What we count as "the legs return to phi" (stated in results.md).
LEGS_ERROR_OK_DEG = 5.0


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
        err = max(record["metrics"]["final_error_deg"].values())
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
            )
        ]
