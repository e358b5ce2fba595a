#!/usr/bin/env bash
# Issue #30: successive jumping across debris. Every run trains on 2 terrains
# (debris seeds 0 and 1, fitness their mean; the walled field, today's
# default: results/debris-open/ holds the runs made on the open field before)
# and is tested on terrains 100-119 it never saw (scripts/debris_table.py).
# Rerun to continue: reproductions and runs resume from their checkpoints. SEEDS="0 1 2" narrows it; BUDGET
# (quick, the default, or long) is the reproduction's budget and sets the
# composed stage's generations in `flat` (quick 30, long 120).
#
#   scripts/debris_study.sh reproduce  the paper on debris at the budget:
#                              rules, kick, getup, return-legs, composed (on
#                              these debris-evolved simples) and the monolithic
#                              network at their total budget, into
#                              runs/debris/<budget>-seed<s>/
#   scripts/debris_study.sh flat       the composed switcher on debris over the
#                              simple networks evolved on the flat floor at the
#                              long budget (results/long-seed0,
#                              results/study/long/seed-<s>), into
#                              runs/debris/flat-simples-composed-s<s>/ (quick)
#                              or runs/debris/long-flat-simples-composed-s<s>/
#   scripts/debris_study.sh both       reproduce, then flat, seed by seed (a
#                              seed's two arms finish before the next starts)
#   scripts/debris_study.sh ship       copy the seeds' finished runs (both
#                              arms) into results/debris/, same names
#                              (scripts/ship_runs.sh: genomes, metrics,
#                              configs; tests/test_study.py replays them)
#   scripts/debris_study.sh table      the study's tables from the shipped runs
#                              (scripts/debris_table.py on terrains 100-119,
#                              as trained and at 12 substeps, the flat floor
#                              beside them), into results/debris/<budget>-
#                              study{,-sub12}.{md,json}, and its learning
#                              curves, docs/figures/debris_learning.png
#   scripts/debris_study.sh status     generations done of every run
set -e
cd "$(dirname "$0")/.."
SEEDS=${SEEDS:-"0 1 2"}
BUDGET=${BUDGET:-quick}
SCENE="--scene debris --terrain-seed 0 --terrains 2"
BIN=.venv/bin/locustjump
flat_simples() {  # the long-budget flat reproduction of seed $1
  if [ "$1" = 0 ]; then echo results/long-seed0; else echo "results/study/long/seed-$1"; fi
}
case $BUDGET in
  quick) COMPOSED=30 PREFIX="" ;;
  long) COMPOSED=120 PREFIX="long-" ;;
  *) echo "BUDGET must be quick or long, not '$BUDGET'" >&2; exit 2 ;;
esac
case $1 in
  reproduce)
    for s in $SEEDS; do
      $BIN reproduce --budget "$BUDGET" --seed "$s" $SCENE --no-videos --quiet \
        --out "runs/debris/$BUDGET-seed$s"
    done ;;
  flat)
    for s in $SEEDS; do
      d=runs/debris/${PREFIX}flat-simples-composed-s$s src=$(flat_simples "$s")
      if [ -f "$d/config.toml" ]; then how=--resume; else
        how="$SCENE --kick $src/kick --getup $src/getup --return-legs $src/return-legs"
      fi
      $BIN train composed --seed "$s" --generations "$COMPOSED" --quiet --out "$d" $how
    done ;;
  both)
    for s in $SEEDS; do
      SEEDS=$s "$0" reproduce
      SEEDS=$s "$0" flat
    done ;;
  ship)
    for s in $SEEDS; do
      scripts/ship_runs.sh runs/debris results/debris "runs/debris/$BUDGET-seed$s"/*/ \
        "runs/debris/${PREFIX}flat-simples-composed-s$s"
    done
    echo "results/debris: $(ls results/debris/*/config.toml results/debris/*/*/config.toml | wc -l) runs" ;;
  table)
    runs="results/debris/$BUDGET-seed*/composed results/debris/$BUDGET-seed*/monolithic"
    runs="$runs results/debris/${PREFIX}flat-simples-composed-s*"
    flat="results/long-seed0 results/study/long/seed-1 results/study/long/seed-2"
    flat="$flat results/study/long/seed-3 results/study/long/seed-4"
    for sub in 3 12; do
      out=results/debris/$BUDGET-study fig="--figure docs/figures/debris_learning.png"
      if [ $sub != 3 ]; then out=$out-sub$sub fig=""; fi
      # shellcheck disable=SC2086  # the globs and options are meant to split
      .venv/bin/python scripts/debris_table.py --terrain-seeds 100-119 --runs $runs \
        --flat-study $flat --substeps $sub --json "$out.json" $fig > "$out.md.tmp" \
        || { rm -f "$out.md.tmp"; exit 1; }
      mv "$out.md.tmp" "$out.md"
      echo "wrote $out.md, $out.json"
    done ;;
  status)
    for d in runs/debris/*/ runs/debris/*/*/; do
      [ -f "$d/config.toml" ] || continue
      echo "$d $(($(wc -l < "$d/metrics.csv") - 1)) generations"
    done ;;
  *) sed -n '2,33p' "$0"; exit 2 ;;
esac
