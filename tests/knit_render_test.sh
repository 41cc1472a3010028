#!/usr/bin/env bash
# knit_render_test.sh FIBERTWIN OUT_DIR — `fibertwin knit` draws the shaded
# frame of `render` (docs/knit-rendering.md): a 2-frame sequence of a small
# stretched stockinette patch writes, per frame, the BCC, the float EXR and
# its PNG, and with --reference the path-traced all-fiber reference (EXR +
# PNG); the log names each frame's cost; --preview keeps the old PNG style.
set -u
FT=$1 OUT=$2
rm -rf "$OUT"
mkdir -p "$OUT"
failed=0
fail() { echo "FAIL  $*"; failed=1; }

log=$("$FT" knit --rows 4 --cols 4 --frames 2 --width 96 --height 72 --self-shadow-size 32 --self-shadow-slices 4 \
      --shadow-map-size 128 --out "$OUT/k.bcc" --image "$OUT/k.exr" --reference "$OUT/ref.exr" --spp 1 2>&1)
rc=$?
echo "$log"
[ $rc -eq 0 ] || fail "knit exited $rc"
for i in 000 001; do
  for f in "k_$i.bcc" "k_$i.exr" "k_$i.png" "ref_$i.exr" "ref_$i.png"; do
    [ -s "$OUT/$f" ] || fail "$f was not written"
  done
done
grep -q "shading inputs baked once for 2 frame(s)" <<<"$log" || fail "no line saying the inputs were baked once"
[ "$(grep -c 'frame [0-9]* ms = shadow map' <<<"$log")" -eq 2 ] || fail "not one cost line per frame"
[ "$(grep -c 'all-fiber reference' <<<"$log")" -eq 2 ] || fail "not one reference line per frame"
# The EXR is float and finite: fibertwin compare reads it back against itself.
"$FT" compare "$OUT/k_001.exr" "$OUT/k_001.exr" --hdr >/dev/null || fail "compare could not read k_001.exr"

"$FT" knit --rows 2 --cols 2 --width 64 --height 48 --preview --out "$OUT/p.bcc" --image "$OUT/p.exr" >/dev/null 2>&1 ||
  fail "knit --preview exited non-zero"
[ -s "$OUT/p.png" ] || fail "--preview did not write p.png"
[ -e "$OUT/p.exr" ] && fail "--preview wrote an EXR"
[ $failed -eq 0 ] && echo "ok    knit shaded frames, reference and preview"
exit $failed
