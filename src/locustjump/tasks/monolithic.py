"""The monolithic baseline (beyond the paper): one 9-10-4 network evolved
directly on the composed behaviour's episode and fitness (Eq. 4), with as many
genome evaluations as the composed controller's four stages together — does
composition help? (``results.md`` answers it: :mod:`locustjump.present.stages`.)
"""

from __future__ import annotations

from typing import ClassVar

from locustjump.tasks.composed import Successive


class Monolithic(Successive):
    """Beyond the paper: one 9-10-4 network on the composed task."""

    name = "monolithic"
    eval_record = ("qpos", "obs", "ctrl")
    gym_id: ClassVar[str | None] = "LocustSuccessiveJump-v0"


__all__ = ["Monolithic"]
