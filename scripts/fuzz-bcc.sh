#!/bin/sh
# fuzz-bcc.sh [seconds] — builds the BCC fuzzer in build-fuzz/ (clang, -DFT_FUZZ=ON)
# and runs it for the given time (default 60 s). The working corpus lives in
# build-fuzz/bcc-corpus (seeded from tests/fuzz_corpus/bcc, kept between runs);
# crashes land in build-fuzz/bcc-artifacts/. Extra arguments go to libFuzzer.
set -eu
seconds=${1:-60}
[ $# -gt 0 ] && shift
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-fuzz"
cxx=${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DFT_FUZZ=ON -DFT_BUILD_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target bcc_fuzzer

mkdir -p "$build/bcc-corpus" "$build/bcc-artifacts"
cp -n "$root"/tests/fuzz_corpus/bcc/* "$build/bcc-corpus/" 2>/dev/null || true
exec "$build/tests/bcc_fuzzer" -max_total_time="$seconds" -artifact_prefix="$build/bcc-artifacts/" \
  -print_final_stats=1 -max_len=4096 "$@" "$build/bcc-corpus"
