#!/usr/bin/env bash
# `fibertwin render` checks the frames it is about to draw (issue 8): with a
# planted NaN fault it must exit non-zero naming the yarn and the knot, and
# write no image; without the fault the same model renders (exit 0).
# Usage: render_refuses_nan_test.sh <fibertwin> <edges.bcc> <out-dir>
set -u
bin=$1 edges=$2 out=$3
mkdir -p "$out"
failed=0
expect_refusal() {  # name, regex the message must match, fibertwin args...
  local name=$1 pattern=$2
  shift 2
  rm -f "$out/refused.png"
  local msg rc
  msg=$("$bin" render "$@" --width 64 --height 48 --out "$out/refused.png" 2>&1)
  rc=$?
  if [ $rc -eq 0 ] || ! grep -Eq "$pattern" <<<"$msg" || [ -e "$out/refused.png" ]; then
    echo "FAIL  $name: exit $rc, image $([ -e "$out/refused.png" ] && echo written || echo absent), message: $msg"
    failed=1
  else
    echo "ok    $name: exit $rc: $msg"
  fi
}
# GPU-only NaN in the closed-loop frame pass: the built-in scene's loop is curve 8.
expect_refusal "closure-axis (GPU only)" 'yarn 8: knot [0-9]+: frame normal \(-?nan' --inject closure-axis
# Shared NaN after the first back-track of edges.bcc: curve 0, knot 5 is its cusp.
expect_refusal "tangent-fallback (shared)" 'yarn 0: knot [0-9]+: frame normal \(-?nan' --inject tangent-fallback \
  --model "$edges"
if ! "$bin" render --model "$edges" --width 64 --height 48 --out "$out/edges.png" >/dev/null || [ ! -s "$out/edges.png" ]; then
  echo "FAIL  edges.bcc without a fault did not render"
  failed=1
fi
exit $failed
