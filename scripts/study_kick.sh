#!/usr/bin/env bash
# Issue #20: optimizers at equal budget on the kick — the paper's budget
# (population 50 x 1000 generations), seeds 0-9 each of rcga, cma, random,
# one thread each, into runs/study/kick-<optimizer>-s<seed>/. Rerun to
# continue: every run resumes from its checkpoint. The engine is pinned to the
# NumPy path, on which this study's first runs were made. Then:
#   .venv/bin/locustjump compare runs/study/kick-* --reference rcga \
#       --figure docs/figures/kick_optimizers.png
set -e
cd "$(dirname "$0")/.."
for s in ${SEEDS:-0 1 2 3 4 5 6 7 8 9}; do
  for opt in rcga cma random; do
    d=runs/study/kick-$opt-s$s
    if [ -f "$d/config.toml" ]; then r=--resume; else r="--engine numpy"; fi
    .venv/bin/locustjump train kick --optimizer $opt --seed "$s" --generations 1000 \
      --threads 1 --quiet --out "$d" $r
  done
done
