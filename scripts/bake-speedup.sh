#!/usr/bin/env bash
# bake-speedup.sh [FIBERTWIN] [SIZE] [DIRECTIONS] [REPEATS] — wall time of the
# AO bake (docs/bakes.md) without mpirun and under mpirun -np 1, 2, with the
# threads per rank that fill this machine's cores, each run REPEATS times
# (interleaved, so a load change hits every configuration alike); every
# output must equal the first byte for byte. Prints "config: best median" seconds.
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
BAKE=(bake ambient-occlusion --size "$SIZE" --directions "$DIRS" --quiet)
configs=("1 rank x 1 thread (no mpirun)|$FT ${BAKE[*]} --threads 1"
         "1 rank x $cores threads (no mpirun)|$FT ${BAKE[*]} --threads $cores"
         "mpirun -np 1 x $cores threads|${MPIRUN[*]} -np 1 $FT ${BAKE[*]} --threads $cores"
         "mpirun -np $cores x 1 thread|${MPIRUN[*]} -np $cores $FT ${BAKE[*]} --threads 1")
declare -A times
for r in $(seq "$REPEATS"); do
  for i in "${!configs[@]}"; do
    cmd=${configs[$i]#*|}
    start=$(date +%s.%N)
    $cmd --out "$TMP/$i.ao"
    end=$(date +%s.%N)
    times[$i]+="$(echo "$end - $start" | bc) "
    cmp "$TMP/0.ao" "$TMP/$i.ao"
  done
done
echo "AO bake ${SIZE}² × $DIRS directions, $cores cores, $REPEATS runs each (wall s, mpirun start-up included; outputs identical):"
for i in "${!configs[@]}"; do
  sorted=$(tr ' ' '\n' <<<"${times[$i]}" | grep . | sort -g)
  best=$(head -1 <<<"$sorted")
  median=$(sed -n "$(( (REPEATS + 1) / 2 ))p" <<<"$sorted")
  printf "  %-40s best %6.2f  median %6.2f\n" "${configs[$i]%%|*}:" "$best" "$median"
done
