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
scripts/ship_runs.sh runs/study results/study runs/study/*/ runs/study/long/seed-*/*/
echo "results/study: $(ls results/study/*/config.toml results/study/long/seed-*/*/config.toml | wc -l) runs"
