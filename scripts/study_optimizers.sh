#!/usr/bin/env bash
# Issue #20, optimizers at equal budget: the tables and the convergence figure
# of one study of docs/science.md, from its finished runs.
#
#   scripts/study_optimizers.sh kick|long-getup|long-return-legs|long-composed [ROOT]
#
# ROOT holds the runs (default results/study, where scripts/study_ship.sh
# puts the finished ones; runs/study/ while they train, unfinished included).
# Prints, for the RCGA (BLX-alpha, the default), its SBX and UNDX variants,
# CMA-ES and random search, seeds 0-9 where present: `locustjump compare`'s
# table (as trained; Mann-Whitney U against the RCGA), then each best genome
# re-simulated at 3, 6, 12 and 24 substeps (scripts/study_substeps.py, the
# same test per resolution); writes docs/figures/<study>_optimizers.png.
set -e
cd "$(dirname "$0")/.."
study=$1 root=${2:-results/study}
case $study in
  kick) what="kick, Eq. 1 E, 50 x 1000" ;;
  long-getup) what="getup, mean U_z, 50 x 20" ;;
  long-return-legs) what="return-legs, -joint error (rad), 50 x 60" ;;
  long-composed) what="composed, Eq. 4 sum of z, 50 x 120" ;;
  *) echo "usage: scripts/study_optimizers.sh kick|long-getup|long-return-legs|long-composed [ROOT]" >&2
     exit 2 ;;
esac
[ -d "$root" ] || { echo "error: $root: no such directory" >&2; exit 2; }
runs=()
for n in rcga cma random rcga-sbx rcga-undx; do
  for d in "$root/$study-$n"-s[0-9]; do [ -f "$d/config.toml" ] && runs+=("$d"); done
done
[ ${#runs[@]} -gt 0 ] || { echo "error: $root holds no $study-* runs" >&2; exit 2; }
fig=docs/figures/${study//-/_}_optimizers.png
.venv/bin/locustjump compare "${runs[@]}" --reference rcga --figure "$fig" --force \
  --title "$what; median and quartiles over seeds"
echo
.venv/bin/python scripts/study_substeps.py "${runs[@]}" --reference rcga
