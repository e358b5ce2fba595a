"""Issue #46: a composition over a kick repertoire in one figure.

Left, the archive of a quality-diversity kick run (MAP-Elites or CMA-ME):
each cell's elite's fitness over the behaviour descriptors, with the elites
that a ``composed-repertoire`` run chooses among numbered in their cells
(0: the best); right, one episode of that run's best switcher (its start on
its side): the body's height over time and, under it, the behaviour chosen
at each control step, elite ``i`` in the colour of its number.

Usage::

    .venv/bin/python scripts/repertoire_figure.py KICK_RUN COMPOSED_RUN \\
        --out docs/figures/repertoire.png [--force]

Exit 2 with one line if a run is not what it should be (not a repertoire, not
a composition over that repertoire's best elites) or ``--out`` exists and
``--force`` is not given; nothing is written then.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from locustjump.errors import UserError
from locustjump.present.repertoire import composition_figure


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("kick", type=Path, help="the quality-diversity kick run")
    ap.add_argument("composed", type=Path, help="the composed-repertoire run")
    ap.add_argument("--out", type=Path, required=True, help="the PNG to write")
    ap.add_argument("--force", action="store_true", help="replace --out")
    args = ap.parse_args(argv)
    try:
        if args.out.suffix != ".png":
            raise UserError(f"--out {args.out}: must name a .png file")
        if args.out.exists() and not args.force:
            raise UserError(f"--out {args.out}: exists (give --force to replace it)")
        if not args.out.parent.is_dir():
            raise UserError(f"--out {args.out}: no such directory {args.out.parent}")
        out = composition_figure(args.kick, args.composed, args.out)
    except UserError as e:
        print(f"repertoire_figure: {e}", file=sys.stderr)
        return 2
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
