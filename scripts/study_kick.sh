#!/usr/bin/env bash
# Issue #20: optimizers at equal budget on the kick — the paper's budget
# (population 50 x 1000 generations), seeds 0-9 each of the RCGA (BLX-alpha,
# the default), its SBX and UNDX variants (scripts/study/rcga-*.toml), CMA-ES
# and random search, one thread each, into runs/study/kick-<name>-s<seed>/.
# Rerun to continue: every run resumes from its checkpoint; JOBS=2 runs two at
# a time. The engine is pinned to the NumPy path, on which this study's first
# runs were made. Then:
#   .venv/bin/locustjump compare runs/study/kick-* --reference rcga \
#       --figure docs/figures/kick_optimizers.png --force
set -e
cd "$(dirname "$0")/.."
one() {  # one run: NAME SEED
  local d=runs/study/kick-$1-s$2 how
  case $1 in
    rcga-*) how="--config scripts/study/$1.toml" ;;
    *) how="--optimizer $1" ;;
  esac
  if [ -f "$d/config.toml" ]; then how=--resume; else how="$how --engine numpy"; fi
  .venv/bin/locustjump train kick --seed "$2" --generations 1000 \
    --threads 1 --quiet --out "$d" $how
}
export -f one
for s in ${SEEDS:-0 1 2 3 4 5 6 7 8 9}; do
  for opt in ${OPTIMIZERS:-rcga cma random rcga-sbx rcga-undx}; do
    echo "$opt $s"
  done
done | xargs -P "${JOBS:-1}" -L 1 bash -c 'one "$@"' _
