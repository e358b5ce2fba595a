"""Getting up's presentation (paper §3.2, Fig. 9): U_z from the five start
states, the 180-state generalisation sweep written into ``DIR/sweep/``, and
the claims "5 of 5" and "65 of 180"."""

from __future__ import annotations

import os
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.present.plots import getup_figure, sweep_figure
from locustjump.present.stages.base import Claim, Episodes, Reporter, fmt, yes
from locustjump.sim import model as lm
from locustjump.sim.engine.job import DEFAULT_ENGINE
from locustjump.sim.scene import Scene
from locustjump.tasks import Behaviour
from locustjump.tasks.getup import (
    SUCCESS_UZ,
    GetUp,
    Sweep,
    sweep_angles,
    sweep_getup,
    up_z,
)

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

FIGURE = "getup.png"  # Fig. 9
#: The paper's generalisation test: got up from 65 of 180 sweep states.
PAPER_SWEEP = 65


class GetUpReporter(Reporter):
    figures = (
        (
            f"{rundir.EVAL}/{FIGURE}",
            "getup",
            "Getting up from the five start states (Fig. 9) and the sweep:",
        ),
        (f"{rundir.SWEEP}/{rundir.SWEEP_PNG}", "sweep", ""),
    )
    headline = ("got_up_from",)

    def write_figures(self, ep: Episodes, out: Path) -> list[Path]:
        """``getup.png``: the paper's Fig. 9, U_z over time from each state."""
        beh, res, p, _ = ep
        assert isinstance(beh, GetUp)  # the reporter of the get-up and its variants
        path = out / FIGURE
        getup_figure(path, up_z(res), beh.rolls, SUCCESS_UZ)
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
        """The paper's generalisation test (180 states): ``run/sweep/``."""
        sw = sweep_getup(
            genome, p, sweep_angles(), backend=backend, engine=engine, scene=beh.scene
        )
        write_sweep(Path(run), sw)
        return {"sweep_got_up": sw.got_up, "sweep_states": sw.n_sweep}

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        five = Claim("gets up from all 5 training states (Fig. 9)", "5 of 5")
        sweep = Claim("gets up from 65 of 180 sweep states", f"{PAPER_SWEEP} of 180")
        if record is None:
            return [five, sweep]
        got_up = sum(record["metrics"]["success"])
        n_sweep = record.get("sweep_states", 180)
        swept = record.get("sweep_got_up")
        ok = swept is not None and swept >= PAPER_SWEEP
        return [
            Claim(
                five.text,
                five.paper,
                f"{got_up} of 5",
                yes(got_up == 5),
                got_up,
                got_up == 5,
                "training states got up (of 5)",
            ),  # fmt: skip
            Claim(
                sweep.text,
                sweep.paper,
                f"{fmt(swept, 'd')} of {n_sweep}",
                f"{yes(ok)} (>= 65)",
                swept,
                ok,
                f"sweep states got up (of {n_sweep})",
            ),
        ]


def write_sweep(run: Path, sw: Sweep) -> list[Path]:
    """``run/sweep/sweep.csv`` and ``sweep.png`` of a sweep."""
    out = run / rundir.SWEEP
    table = np.column_stack(
        [sw.roll_deg, sw.training, sw.success, sw.start_uz, sw.final_uz,
         sw.time_to_get_up_s]
    )  # fmt: skip

    def write(f: IO[bytes]) -> None:
        np.savetxt(
            f,
            table,
            delimiter=",",
            header="angle_deg,training,success,start_uz,final_uz,time_to_get_up_s",
            comments="",
            fmt=["%.6g", "%d", "%d", "%.6f", "%.6f", "%.6g"],
        )

    with rundir.made_dir(out):  # removed again if a write fails
        rundir.atomic_write_bytes(out / rundir.SWEEP_CSV, write)
        sweep_figure(out / rundir.SWEEP_PNG, sw)
    return [out / rundir.SWEEP_CSV, out / rundir.SWEEP_PNG]


def sweep_run(
    path: str | os.PathLike[str],
    angles: np.ndarray,
    *,
    backend: Backend | None = None,
    scene: Scene | None = None,
) -> tuple[Sweep, list[Path]]:
    """The get-up generalisation test of getup run ``path``'s best genome from
    roll ``angles`` (plus the training states): ``DIR/sweep/sweep.csv`` and
    ``sweep.png`` (a shipped run's under ``runs/shipped/``:
    :func:`locustjump.rundir.derived_dir`)."""
    cfg, _, best = rundir.load_run(path)
    if cfg.behaviour != GetUp.name:
        raise UserError(
            f"{path}: holds a {cfg.behaviour!r} run; sweep-getup needs a getup run"
        )
    # from the simulation to the last file (a shipped run is not written)
    with rundir.deriving(Path(path)) as dest:
        sw = sweep_getup(best.genome, cfg.model, angles, backend=backend,
                         engine=cfg.engine, scene=scene or cfg.scene.scene)  # fmt: skip
        return sw, write_sweep(dest, sw)
