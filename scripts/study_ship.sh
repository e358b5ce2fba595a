#!/usr/bin/env bash
# Issue #20: copy the finished study runs that back docs/science.md from
# runs/study/ into results/study/ — config.toml, metrics.csv, best.npz (and a
# composed run's simple.npz): what `locustjump evaluate` re-simulates and
# `locustjump compare` reads; no checkpoints, figures or trajectories. The
# trained stages of the long-budget seeds (runs/study/long/seed-N/STAGE, the
# composition-vs-monolithic table) go to results/study/long/seed-N/STAGE.
# A run is finished when metrics.csv has its config's generations.
set -e
cd "$(dirname "$0")/.."
for d in runs/study/*/ runs/study/long/seed-*/*/; do
  d=${d%/}
  [ -f "$d/config.toml" ] && [ -f "$d/best.npz" ] || continue
  want=$(sed -n 's/^generations = //p' "$d/config.toml")
  have=$(($(wc -l < "$d/metrics.csv") - 1))
  [ "$have" = "$want" ] || { echo "skip $d: $have of $want generations"; continue; }
  out=results/study/${d#runs/study/}
  mkdir -p "$out"
  for f in config.toml metrics.csv best.npz simple.npz; do
    [ -f "$d/$f" ] && cp "$d/$f" "$out/$f"
  done
done
echo "results/study: $(ls results/study/*/config.toml results/study/long/seed-*/*/config.toml | wc -l) runs"
