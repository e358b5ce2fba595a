"""How a behaviour is shown: its figures, its rows and sections of
``results.md``, the numbers ``replay`` prints and the evaluations beyond its
episodes. The behaviour itself (:mod:`locustjump.tasks`) is the task spec:
start states, episode, controller, fitness and metrics; a :class:`Reporter`
turns what it measured into figures and tables."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import numpy as np

from locustjump.present.plots import trajectory_figure
from locustjump.rundir.layout import EVAL, TRAJECTORY_PNG
from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps, ground_profile
from locustjump.sim.engine.job import DEFAULT_ENGINE, RolloutResult
from locustjump.tasks import Behaviour
from locustjump.tasks.reference import RulesRun

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


class Episodes(NamedTuple):
    """One controller's episodes as an evaluation simulated them: what a
    reporter draws its figures from."""

    behaviour: Behaviour
    res: RolloutResult  # its episodes (one per start state)
    params: lm.LocustParams  # the creature they ran on
    #: the behaviour's rule-based reference (``Behaviour.reference``), simulated
    #: once for its metrics and its figures
    reference: RulesRun | None = None


@dataclass(frozen=True)
class Claim:
    """One row of ``results.md``: a claim of the paper and how ours compares.

    ``ours`` is ``None`` while the stage has not run yet. ``value`` (what
    ``measure`` names) and ``ok`` are the number and the verdict as data, which
    the summary across seeds reduces to a median, a range and a count. Under
    the table, a failing claim gets ``reason``, why *this run* misses it (read
    from its own numbers), and ``why``, what a study measured about the
    reason beyond this run (docs/science.md).
    """

    text: str  # the claim, as the paper makes it (figure in parentheses)
    paper: str  # the paper's number
    ours: str | None = None  # our number
    verdict: str = "-"  # "**yes**"/"no" and our criterion in parentheses
    value: float | None = None  # the number the verdict is about
    ok: bool | None = None  # reproduced by our criterion
    measure: str = ""  # what ``value`` is, with its unit
    why: str = ""  # what is known of why it fails, beyond this run (a study)
    reason: str = ""  # why this run misses it, from its own numbers

    def row(self) -> str:
        ours = (
            "not run yet | -" if self.ours is None else f"{self.ours} | {self.verdict}"
        )
        return f"| {self.text} | {self.paper} | {ours} |"


def yes(ok: bool) -> str:
    """The verdict word of a claim row."""
    return "**yes**" if ok else "no"


def fmt(x: float | None, spec: str = ".2f", unit: str = "") -> str:
    """A number of a claim row with its ``unit`` ("x", " m"); ``n/a``, with
    no unit, where there is none (not "n/ax")."""
    return "n/a" if x is None else format(x, spec) + unit


class Reporter:
    """The presentation of one behaviour; every hook has a default that fits a
    plain behaviour (a trajectory figure, no claims, no sections).

    ==========================  ================================================
    ``figures``                 (file in the run directory, alt text, caption
                                in ``results.md``) of each figure
    ``headline``                the metrics ``locustjump replay`` prints
    :meth:`write_figures`       its figures of one controller's episodes
    :meth:`extra_evaluation`    evaluations beyond the episodes (getup's sweep)
    :meth:`claims`              its rows of ``results.md``
    :meth:`report_section`      a section of ``results.md`` of its own
    :meth:`across_seeds`        its section of a reproduction over seeds
    ==========================  ================================================
    """

    figures: ClassVar[tuple[tuple[str, str, str], ...]] = (
        (f"{EVAL}/{TRAJECTORY_PNG}", "trajectory", ""),
    )
    headline: ClassVar[tuple[str, ...]] = ("fitness",)

    def write_figures(self, ep: Episodes, out: Path) -> list[Path]:
        """Figures of one controller's episodes ``ep`` into directory ``out``."""
        beh, res, p, _ = ep
        path = out / TRAJECTORY_PNG
        qpos = res["qpos"][0]
        trajectory_figure(
            path,
            [(beh.name, qpos, find_jumps(qpos, p, beh.scene))],
            ground=ground_profile(qpos, p, beh.scene),
        )
        return [path]

    def extra_evaluation(
        self,
        beh: Behaviour,
        run: Path,
        genome: np.ndarray,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
        engine: str = DEFAULT_ENGINE,
    ) -> dict[str, Any]:
        """Evaluations beyond the episodes, written into run directory ``run``;
        the numbers they give (merged into ``eval/metrics.json``)."""
        return {}

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        """Rows of ``results.md`` from this stage's ``eval/metrics.json``
        (``None``: not run yet)."""
        return []

    def report_section(self, stages: dict[str, dict[str, Any]]) -> list[str]:
        """Markdown lines of a ``results.md`` section of its own, from every
        finished stage's summary (:func:`locustjump.present.results.stage_summary`)."""
        return []

    def across_seeds(self, seeds: dict[int, dict[str, dict[str, Any]]]) -> list[str]:
        """Markdown lines of its own section of a reproduction over several
        seeds: ``seeds`` maps each seed to its finished stages' summaries."""
        return []
