"""Do the rule-based jumps ever get smaller, as in the paper's Fig. 5?

Runs the rule-based controller for 3000 control steps at every kick posture
of a grid (hip x knee, degrees) and several change times, and prints, per
setting, the number of jumps, the spread of the "full" jumps' apex heights
(jumps above half of the highest one; failed kicks are the others) and whether
the later full jumps are lower than the first ones. Evidence for the known gap
in ``docs/physics.md``.

    python scripts/rules_posture_grid.py
"""

from __future__ import annotations

import itertools

import numpy as np

from locustjump import analysis
from locustjump import model as lm
from locustjump.rollout import StartStates, rollout
from locustjump.rules import RuleController

HIPS = range(60, 131, 10)
KNEES = range(100, 161, 15)
CHANGE_TIMES = (0.25, 0.5, 0.75, 1.0)


def main() -> None:
    p = lm.LocustParams()
    starts = StartStates.ready(lm.load_model(p))
    declining, settings, spreads = 0, 0, []
    print(
        "hip knee change | jumps  full  full-jump apex first..last (m)  "
        "spread but last  final U_z"
    )
    for hip, knee in itertools.product(HIPS, KNEES):
        kick = p.replace(kick_hip=float(hip), kick_knee=float(knee)).kick_angles()
        rc = RuleController(tuple(p.ready_angles()), tuple(kick))
        cts = np.asarray(CHANGE_TIMES)
        res = rollout(
            rc, rc.params_for(cts), starts, 3000, model_params=p,
            record=("qpos", "obs"),
        )  # fmt: skip
        for i, ct in enumerate(cts):
            jumps = analysis.find_jumps(res["qpos"][i], p)
            apex = np.array([j.apex_height for j in jumps])
            full = apex[apex > 0.5 * apex.max()] if apex.size else apex
            settings += 1
            # a Fig. 5-like decline: three full jumps in a row, each > 2 % lower
            drops = full[1:] < 0.98 * full[:-1]
            dec = bool((drops[1:] & drops[:-1]).any())
            declining += dec
            # how much the full jumps differ before the last one (often a
            # lower jump just before the creature overturns)
            body = full[:-1]
            spread = (body.max() - body.min()) / body.max() if body.size > 1 else 0.0
            spreads.append(spread)
            span = f"{full[0]:.3f}..{full[-1]:.3f}" if full.size else "-"
            print(
                f"{hip:3d} {knee:4d} {ct:6.2f} | {apex.size:5d} {full.size:5d}  "
                f"{span:>29}  {spread:14.1%}  {res['obs'][i, -1, 8]:+9.2f}"
                + ("  declining" if dec else "")
            )
    print(
        f"{declining} of {settings} settings show a declining run of jumps; "
        f"median spread of the full jumps before the last: "
        f"{np.median(spreads):.1%} (largest {max(spreads):.1%})"
    )


if __name__ == "__main__":
    main()
