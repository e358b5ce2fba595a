#!/usr/bin/env bash
# Copy finished runs into results/: scripts/ship_runs.sh FROM TO RUN...
# copies each RUN (a run directory under FROM) to TO/<its path under FROM>:
# config.toml, metrics.csv, best.npz, a composed run's frozen genomes
# (frozen.npz, or simple.npz in older runs) and a quality-diversity run's
# archive (archive.npz) — what `locustjump evaluate` re-simulates and
# tests/test_study.py replays; no checkpoints, figures or trajectories. A
# run is finished when metrics.csv has its config's generations; others are
# skipped (and named). A whole study: scripts/ship_study.py.
set -e
from=${1%/} to=${2%/}
shift 2
for d in "$@"; do
  d=${d%/}
  [ -f "$d/config.toml" ] && [ -f "$d/best.npz" ] || continue
  want=$(sed -n 's/^generations = //p' "$d/config.toml")
  have=$(($(wc -l < "$d/metrics.csv") - 1))
  [ "$have" = "$want" ] || { echo "skip $d: $have of $want generations"; continue; }
  out=$to/${d#"$from"/}
  mkdir -p "$out"
  for f in config.toml metrics.csv best.npz frozen.npz simple.npz archive.npz; do
    if [ -f "$d/$f" ]; then cp "$d/$f" "$out/$f"; fi
  done
done
