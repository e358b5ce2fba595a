#!/usr/bin/env bash
# Issue #20's training runs, one thread each, into runs/study/<behaviour>-<name>-s<seed>/.
# Rerun to continue: every run resumes from its checkpoint. JOBS=2 runs two at
# a time; SEEDS="0 1" and NAMES="rcga cma" narrow a study.
#
#   scripts/study.sh kick      the kick at the paper's budget (50 x 1000), seeds
#                              0-9 of the RCGA (BLX-alpha, the default), its SBX
#                              and UNDX variants (scripts/study/rcga-*.toml),
#                              CMA-ES and random search; NumPy engine path, on
#                              which the study's first runs were made
#   scripts/study.sh ceiling   the kick's ceiling: apex fitness and/or open-loop
#                              control (kick-apex, kick-apex-open, kick-open),
#                              CMA-ES and the RCGA, 50 x 1000, seeds 0-2
#   scripts/study.sh long      getup, return-legs and composed at the long
#                              budget of `reproduce` (population 50; 20, 60
#                              and 120 generations; composed on the simple
#                              networks of results/long-seed0, switching
#                              every 120 steps), seeds 0-2 of the RCGA, its
#                              SBX and UNDX variants, CMA-ES and random
#                              search; into runs/study/long-<behaviour>-...
#   scripts/study.sh composed  the composed behaviour on the simple networks of
#                              results/paper-seed0, 50 x 300, switching every
#                              120 (the paper) or 10 steps (pN), with the
#                              paper's kick or the kick-apex-cma-s0 one (apex-),
#                              evolved by the RCGA or CMA-ES (cma-), the
#                              physics at 3 (the default) or 6 substeps (sub6-),
#                              each genome scored as its worst of 3 and 6
#                              (robust6-) or of 3, 6 and 12 substeps (robust-)
#
#   scripts/study.sh status    every run under runs/study: generations done
#                              of its config's, unfinished ones first
#
# Then e.g. (docs/science.md has every command):
#   .venv/bin/locustjump compare runs/study/kick-{rcga,cma,random}-s* --reference rcga
set -e
cd "$(dirname "$0")/.."
one() {  # one run: BEHAVIOUR NAME SEED ENGINE GENERATIONS
  local d=runs/study/$1-$2-s$3 how simple=results/paper-seed0 kick
  case $1 in long-*) simple=results/long-seed0 ;; esac
  case $1/$2 in
    */rcga-*) how="--config scripts/study/$2.toml" ;;
    composed/*) kick=$simple/kick how=
       case $2 in *apex-*) kick=runs/study/kick-apex-cma-s0 ;; esac
       case $2 in cma-*) how="--optimizer cma" ;; esac
       case $2 in *sub6-*) how="$how --config scripts/study/substeps6.toml" ;; esac
       case $2 in
         *robust6-*) how="$how --score-substeps 6" ;;
         *robust-*) how="$how --score-substeps 6,12" ;;
       esac
       how="$how --switch-every ${2##*p} --kick $kick --getup $simple/getup
            --return-legs $simple/return-legs" ;;
    *) how="--optimizer $2" ;;
  esac
  case $1 in long-composed)
    how="$how --kick $simple/kick --getup $simple/getup --return-legs $simple/return-legs" ;;
  esac
  if [ -f "$d/config.toml" ]; then how=--resume; else how="$how --engine $4"; fi
  .venv/bin/locustjump train "${1#long-}" --seed "$3" --generations "$5" \
    --threads 1 --quiet --out "$d" $how
}
export -f one
if [ "$1" = status ]; then
  for d in runs/study/*/ runs/study/long/seed-*/*/; do
    [ -f "$d/config.toml" ] || continue
    want=$(sed -n 's/^generations = //p' "$d/config.toml")
    have=$(($(wc -l < "$d/metrics.csv" 2>/dev/null || echo 1) - 1))
    printf '%s %s/%s\n' "$([ "$have" = "$want" ] && echo done || echo running)" "$have" "$want ${d%/}"
  done | sort -k1,1r -k3
  exit 0
fi
gens=1000
case $1 in
  kick) behaviours=kick names="rcga cma random rcga-sbx rcga-undx"
        seeds="0 1 2 3 4 5 6 7 8 9" engine=numpy ;;
  ceiling) behaviours="kick-apex kick-apex-open kick-open" names="cma rcga"
           seeds="0 1 2" engine=numba ;;
  long) behaviours="long-getup long-return-legs long-composed"
        names="rcga cma random rcga-sbx rcga-undx" seeds="0 1 2" engine=numba ;;
  composed) behaviours=composed
            names="p10 apex-p10 apex-sub6-p10 apex-p120 cma-p120 apex-robust6-p10"
            seeds=0 engine=numba gens=300 ;;
  *) echo "usage: scripts/study.sh kick|ceiling|long|composed|status" >&2; exit 2 ;;
esac
for s in ${SEEDS:-$seeds}; do
  for b in $behaviours; do
    case $b in  # the long budget of reproduce
      long-getup) g=20 ;; long-return-legs) g=60 ;; long-composed) g=120 ;; *) g=$gens ;;
    esac
    for n in ${NAMES:-$names}; do echo "$b $n $s $engine $g"; done
  done
done | xargs -P "${JOBS:-1}" -L 1 bash -c 'one "$@"' _
