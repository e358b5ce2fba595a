#!/usr/bin/env bash
# Issue #20: copy the finished study runs that back docs/science.md from
# runs/study/ into results/study/ — config.toml, metrics.csv, best.npz (and a
# composed run's simple.npz): what `locustjump evaluate` re-simulates and
# `locustjump compare` reads; no checkpoints, figures or trajectories.
# A run is finished when metrics.csv has its config's generations.
set -e
cd "$(dirname "$0")/.."
for d in runs/study/*/; do
  d=${d%/}
  [ -f "$d/config.toml" ] && [ -f "$d/best.npz" ] || continue
  want=$(sed -n 's/^generations = //p' "$d/config.toml")
  have=$(($(wc -l < "$d/metrics.csv") - 1))
  [ "$have" = "$want" ] || { echo "skip $d: $have of $want generations"; continue; }
  out=results/study/$(basename "$d")
  mkdir -p "$out"
  for f in config.toml metrics.csv best.npz simple.npz; do
    [ -f "$d/$f" ] && cp "$d/$f" "$out/$f"
  done
done
echo "results/study: $(ls -d results/study/*/ | wc -l) runs"
