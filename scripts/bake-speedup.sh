#!/usr/bin/env bash
# bake-speedup.sh [FIBERTWIN] [SIZE] [DIRECTIONS] [REPEATS] [BAKE ARGS...] — wall
# time of a bake (docs/bakes.md; the AO bake at SIZE² × DIRECTIONS, or the bake
# and options given after REPEATS, e.g. `iirtf --fibers-per-ply 0 --paths 2000`,
# SIZE and DIRECTIONS then unused) without mpirun and under mpirun -np 1, 2, with the
# threads per rank that fill this machine's cores, each run REPEATS times
# (interleaved, so a load change hits every configuration alike); every
# output must equal the first byte for byte. Prints per configuration the best
# and median wall seconds and the median CPU seconds (user + sys, all ranks),
# and the load average before and after (other work on the machine shows there).
set -euo pipefail
FT=${1:-build/release/cli/fibertwin}
SIZE=${2:-384}
DIRS=${3:-64}
REPEATS=${4:-3}
cores=$(nproc)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/fibertwin-speedup.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export OMPI_MCA_btl_vader_single_copy_mechanism=none
MPIRUN=(mpirun --allow-run-as-root --oversubscribe --bind-to none)
if (( $# > 4 )); then
  BAKE=(bake "${@:5}" --quiet)
  LABEL="${*:5}"
else
  BAKE=(bake ambient-occlusion --size "$SIZE" --directions "$DIRS" --quiet)
  LABEL="AO bake ${SIZE}² × $DIRS directions"
fi
configs=("1 rank x 1 thread (no mpirun)|$FT ${BAKE[*]} --threads 1"
         "1 rank x $cores threads (no mpirun)|$FT ${BAKE[*]} --threads $cores"
         "mpirun -np 1 x $cores threads|${MPIRUN[*]} -np 1 $FT ${BAKE[*]} --threads $cores"
         "mpirun -np $cores x 1 thread|${MPIRUN[*]} -np $cores $FT ${BAKE[*]} --threads 1")
declare -A wall cpu
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
TIMEFORMAT='%R %U %S'
for r in $(seq "$REPEATS"); do
  for i in "${!configs[@]}"; do
    cmd=${configs[$i]#*|}
    { time $cmd --out "$TMP/$i.ao" 2>"$TMP/err"; } 2>"$TMP/time"
    read -r real user sys <"$TMP/time"
    wall[$i]+="$real "
    cpu[$i]+="$(echo "$user + $sys" | bc) "
    cmp "$TMP/0.ao" "$TMP/$i.ao"
  done
done
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | sed -n "$(( (REPEATS + 1) / 2 ))p"; }
echo "$LABEL, $cores cores, $REPEATS runs each, outputs identical;"
echo "load average before $load_before, after $(cut -d' ' -f1-3 /proc/loadavg):"
for i in "${!configs[@]}"; do
  best=$(tr ' ' '\n' <<<"${wall[$i]}" | grep . | sort -g | head -1)
  printf "  %-40s wall best %6.2f s  median %6.2f s   CPU median %6.2f s\n" "${configs[$i]%%|*}:" "$best" \
    "$(median "${wall[$i]}")" "$(median "${cpu[$i]}")"
done
