"""Do the rule-based jumps ever get smaller, as in the paper's Fig. 5?

Runs the rule-based controller for 3000 control steps

1. at every kick posture of a grid (hip x knee, degrees), rigid fore and middle
   legs (the trained creature), and
2. at the default kick posture with the fore and middle legs on sprung hinges
   (``LocustParams.strut_stiffness``) of several stiffnesses,

each at several change times, and prints, per setting, the number of jumps,
the spread of the "full" jumps' apex heights (jumps above half of the highest
one; failed kicks are the others) and whether the later full jumps are lower
than the first ones. Evidence for the known gap in ``docs/physics.md``.

    python scripts/rules_posture_grid.py
"""

from __future__ import annotations

import itertools

import numpy as np

from locustjump.sim import analysis, names
from locustjump.sim import model as lm
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.tasks.rules import RuleController

HIPS = range(60, 131, 10)
KNEES = range(100, 161, 15)
CHANGE_TIMES = (0.25, 0.5, 0.75, 1.0)
#: (N m/rad, real scale) sprung fore/middle legs; the smallest lets the middle
#: legs sag until the abdomen tip and hind tarsi carry the body (about 1 deg)
STRUT_STIFFNESSES = (2.5e-6, 1e-5, 5e-5, 2e-4)


class Tally:
    """Counts settings with a Fig. 5-like decline; prints one line a setting."""

    spreads: list[float]

    def __init__(self) -> None:
        self.declining, self.settings, self.spreads = 0, 0, []

    def add(
        self, label: str, qpos: np.ndarray, up_z: float, p: lm.LocustParams
    ) -> None:
        jumps = analysis.find_jumps(qpos, p)
        apex = np.array([j.apex_height for j in jumps])
        full = apex[apex > 0.5 * apex.max()] if apex.size else apex
        self.settings += 1
        # a Fig. 5-like decline: three full jumps in a row, each > 2 % lower
        drops = full[1:] < 0.98 * full[:-1]
        dec = bool((drops[1:] & drops[:-1]).any())
        self.declining += dec
        # how much the full jumps differ before the last one (often a lower
        # jump just before the creature overturns)
        body = full[:-1]
        spread = (body.max() - body.min()) / body.max() if body.size > 1 else 0.0
        self.spreads.append(spread)
        span = f"{full[0]:.3f}..{full[-1]:.3f}" if full.size else "-"
        print(
            f"{label} | {apex.size:5d} {full.size:5d}  {span:>29}  "
            f"{spread:14.1%}  {up_z:+9.2f}" + ("  declining" if dec else "")
        )

    def summary(self) -> None:
        print(
            f"{self.declining} of {self.settings} settings show a declining run of "
            f"jumps; median spread of the full jumps before the last: "
            f"{np.median(self.spreads):.1%} (largest {max(self.spreads):.1%})\n"
        )


COLUMNS = "jumps  full  full-jump apex first..last (m)  spread but last  final U_z"


def run(p: lm.LocustParams, rc: RuleController) -> tuple[np.ndarray, np.ndarray]:
    res = rollout(
        rc, rc.params_for(np.asarray(CHANGE_TIMES)),
        StartStates.ready(lm.load_model(p)), 3000, model_params=p,
        record=("qpos", "obs"),
    )  # fmt: skip
    return res["qpos"], res["obs"][:, -1, 8]


def main() -> None:
    p = lm.LocustParams()
    print("Rigid fore and middle legs, kick posture grid")
    print(f"hip knee change | {COLUMNS}")
    tally = Tally()
    for hip, knee in itertools.product(HIPS, KNEES):
        kick = p.replace(kick_hip=float(hip), kick_knee=float(knee)).kick_angles()
        qpos, up_z = run(p, RuleController(tuple(p.ready_angles()), tuple(kick)))
        for i, ct in enumerate(CHANGE_TIMES):
            tally.add(f"{hip:3d} {knee:4d} {ct:6.2f}", qpos[i], up_z[i], p)
    tally.summary()

    print("Sprung fore and middle legs, default kick posture")
    print(f"stiffness change  sag | {COLUMNS}")
    tally = Tally()
    for k in STRUT_STIFFNESSES:
        ps = p.replace(strut_stiffness=k)
        m = lm.load_model(ps)
        mid = m.jnt_qposadr[m.joint(names.MID_LEGS[0]).id]
        sag = np.degrees(m.key(lm.READY_KEY).qpos[mid])
        qpos, up_z = run(ps, RuleController.for_model(ps))
        for i, ct in enumerate(CHANGE_TIMES):
            tally.add(f"{k:9.1e} {ct:6.2f} {sag:4.1f}", qpos[i], up_z[i], ps)
    tally.summary()


if __name__ == "__main__":
    main()
