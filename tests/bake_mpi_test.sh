#!/usr/bin/env bash
# bake_mpi_test.sh FIBERTWIN WITH_MPI — `fibertwin bake` across MPI ranks
# (bake/bake_runner.h, docs/bakes.md):
#   WITH_MPI=1: the AO bake under `mpirun -np 1, 2, 3` and the ξ bake
#     (ds-correction), the segment visibility bake (segment-visibility) and
#     the IIRTF bake (iirtf, A_C and its standard errors) under `mpirun -np 2` are byte for byte the ones without mpirun (the determinism contract: `cmp` is the check); a
#     failure planted on a worker rank and on rank 0's worker thread
#     (FT_BAKE_FAIL_RANK) ends the job with the message, a non-zero status
#     and no output, well within the timeout (no rank left waiting); an
#     unwritable --out under mpirun names the option.
#   WITH_MPI=0 (built without MPI): under mpirun the bake refuses to run.
# Exit 77 (ctest SKIP_RETURN_CODE) only when mpirun is not installed.
set -u

if [ $# -ne 2 ]; then
  echo "usage: $0 FIBERTWIN WITH_MPI(0|1)" >&2
  exit 2
fi
FT=$1
WITH_MPI=$2
if ! command -v mpirun >/dev/null; then
  echo "mpirun not installed (apt-get install openmpi-bin libopenmpi-dev): skipped"
  exit 77
fi
TMP=$(mktemp -d "${TMPDIR:-/tmp}/fibertwin-bake-mpi.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

# Root in CI; more ranks than cores on a 2-core machine. In containers without
# ptrace rights Open MPI's single-copy shared memory (CMA) fails: plain copies.
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
export OMPI_MCA_btl_vader_single_copy_mechanism=none
# 48² texels × 16 directions in 48 shards of one row: a fraction of a second.
BAKE=(bake ambient-occlusion --yarn rayon2 --size 48 --directions 16 --rows-per-shard 1)

failed=0
fail() {
  echo "FAIL  $1"
  [ -n "${2:-}" ] && sed 's/^/        | /' "$2" | head -20
  failed=$((failed + 1))
}
ok() { echo "ok    $1"; }

if [ "$WITH_MPI" != 1 ]; then
  timeout 60 "${MPIRUN[@]}" -np 2 "$FT" "${BAKE[@]}" --out "$TMP/x.ao" >"$TMP/out" 2>"$TMP/err"
  rc=$?
  if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "built without MPI" "$TMP/err" && [ ! -e "$TMP/x.ao" ]; then
    ok "built without MPI: mpirun -np 2 refused (status $rc)"
  else
    fail "built without MPI: mpirun -np 2 gave status $rc" "$TMP/err"
  fi
  exit $((failed > 0))
fi

if "$FT" "${BAKE[@]}" --out "$TMP/one.ao" >"$TMP/out" 2>"$TMP/err"; then
  ok "no mpirun: $(tail -1 "$TMP/out")"
else
  fail "no mpirun: status $?" "$TMP/err"
  exit 1
fi
for np in 1 2 3; do
  if timeout 120 "${MPIRUN[@]}" -np $np "$FT" "${BAKE[@]}" --out "$TMP/np$np.ao" >"$TMP/out" 2>"$TMP/err"; then
    if cmp "$TMP/one.ao" "$TMP/np$np.ao"; then
      ok "mpirun -np $np: identical to the run without mpirun: $(tail -1 "$TMP/out")"
    else
      fail "mpirun -np $np: output differs from the run without mpirun"
    fi
    grep -q "on $np rank" "$TMP/out" || fail "mpirun -np $np: the summary does not say $np ranks" "$TMP/out"
  else
    fail "mpirun -np $np: status $?" "$TMP/err"
  fi
done

# The path-traced bake of 001 §4.3 (ξ, one shard per light direction) at CI
# size: its shards finish out of order across ranks; the file must not care.
XI=(bake ds-correction --height 8 --theta-samples 4 --phi-samples 4 --spp 4 --periods 3)
if "$FT" "${XI[@]}" --out "$TMP/xi-one.bin" >"$TMP/out" 2>"$TMP/err"; then
  if timeout 120 "${MPIRUN[@]}" -np 2 "$FT" "${XI[@]}" --out "$TMP/xi-np2.bin" >"$TMP/out" 2>"$TMP/err"; then
    if cmp "$TMP/xi-one.bin" "$TMP/xi-np2.bin"; then
      ok "ds-correction, mpirun -np 2: identical to the run without mpirun: $(tail -1 "$TMP/out")"
    else
      fail "ds-correction, mpirun -np 2: output differs from the run without mpirun"
    fi
  else
    fail "ds-correction, mpirun -np 2: status $?" "$TMP/err"
  fi
else
  fail "ds-correction, no mpirun: status $?" "$TMP/err"
fi

# The segment visibility bake of 004 §4.1 (sharded by segment ranges, the PCA
# on rank 0 in write()) at CI size: 64 segments, 16² images, 16 shards.
SVF=(bake segment-visibility --fibers-per-ply 2 --spans 4 --subdivisions 1 --tiles 3 --width 16 --height 16
  --components 16 --segments-per-shard 4)
if "$FT" "${SVF[@]}" --out "$TMP/svf-one.bin" >"$TMP/out" 2>"$TMP/err"; then
  if timeout 120 "${MPIRUN[@]}" -np 2 "$FT" "${SVF[@]}" --out "$TMP/svf-np2.bin" >"$TMP/out" 2>"$TMP/err"; then
    if cmp "$TMP/svf-one.bin" "$TMP/svf-np2.bin"; then
      ok "segment-visibility, mpirun -np 2: identical to the run without mpirun: $(tail -1 "$TMP/out")"
    else
      fail "segment-visibility, mpirun -np 2: output differs from the run without mpirun"
    fi
  else
    fail "segment-visibility, mpirun -np 2: status $?" "$TMP/err"
  fi
else
  fail "segment-visibility, no mpirun: status $?" "$TMP/err"
fi

# The IIRTF bake of 004 §4.2 (one shard per cell, paths keyed by segment and
# path index) at CI size: the default block (768 segments), 3 × 3 tiles, a few cells of 5,000 paths.
# The file is version 2: A_C and the standard error of each entry, both under the cmp.
IIRTF=(bake iirtf --tiles 3 --cell-size 0.12 --paths 5000 --ell-paths 200)
if "$FT" "${IIRTF[@]}" --out "$TMP/iirtf-one.bin" >"$TMP/out" 2>"$TMP/err"; then
  head -1 "$TMP/iirtf-one.bin" | grep -q '"version":2' || fail "iirtf: the file is not version 2 (no standard errors)"
  if timeout 120 "${MPIRUN[@]}" -np 2 "$FT" "${IIRTF[@]}" --out "$TMP/iirtf-np2.bin" >"$TMP/out" 2>"$TMP/err"; then
    if cmp "$TMP/iirtf-one.bin" "$TMP/iirtf-np2.bin"; then
      ok "iirtf, mpirun -np 2: identical to the run without mpirun: $(tail -1 "$TMP/out")"
    else
      fail "iirtf, mpirun -np 2: output differs from the run without mpirun"
    fi
  else
    fail "iirtf, mpirun -np 2: status $?" "$TMP/err"
  fi
else
  fail "iirtf, no mpirun: status $?" "$TMP/err"
fi

# A planted failure: rank 1 (a worker rank) and rank 0 (the coordinator's worker thread).
for rank in 1 0; do
  start=$(date +%s)
  timeout 60 "${MPIRUN[@]}" -np 2 -x FT_BAKE_FAIL_RANK=$rank "$FT" "${BAKE[@]}" --out "$TMP/fail.ao" \
    >"$TMP/out" 2>"$TMP/err"
  rc=$?
  secs=$(($(date +%s) - start))
  if [ $rc -eq 124 ]; then
    fail "failure on rank $rank: the job hung (killed after 60 s)" "$TMP/err"
  elif [ $rc -eq 0 ]; then
    fail "failure on rank $rank: status 0" "$TMP/err"
  elif ! grep -q "rank $rank: bake ambient-occlusion: shard [0-9]* of 48: planted failure on rank $rank" "$TMP/err"; then
    fail "failure on rank $rank: stderr lacks the rank, shard and message" "$TMP/err"
  elif [ -e "$TMP/fail.ao" ] || [ -e "$TMP/fail.ao.part" ]; then
    fail "failure on rank $rank: an output file was left"
  else
    ok "failure on rank $rank: status $rc after ${secs} s, message: $(grep -m1 'planted failure' "$TMP/err")"
  fi
done

timeout 60 "${MPIRUN[@]}" -np 2 "$FT" "${BAKE[@]}" --out "$TMP/no-such-folder/x.ao" >"$TMP/out" 2>"$TMP/err"
rc=$?
if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q -- "--out: '$TMP/no-such-folder/x.ao'" "$TMP/err"; then
  ok "mpirun -np 2 --out in a missing folder: status $rc, names --out"
else
  fail "mpirun -np 2 --out in a missing folder: status $rc" "$TMP/err"
fi

[ $failed -eq 0 ] && echo "bake_mpi_test: all passed" || echo "bake_mpi_test: $failed failed"
exit $((failed > 0))
