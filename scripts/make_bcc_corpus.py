#!/usr/bin/env python3
"""Writes the BCC fuzz seed corpus (tests/fuzz_corpus/bcc/): small valid files
and one file per class of malformation, so the fuzzer starts next to every
error path of scene/bcc_reader.cpp. Deterministic; rerun to regenerate."""
import math
import os
import struct
import sys

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fuzz_corpus", "bcc")


def header(curves, points, up=1, sig=b"BCC", counts=0x44, ctype=b"C0", dims=3):
    h = sig + bytes([counts]) + ctype + bytes([dims, up]) + struct.pack("<QQ", curves, points)
    return h + b"corpus".ljust(40, b"\0")


def curve(pts, closed=False):
    n = -len(pts) if closed else len(pts)
    return struct.pack("<i", n) + b"".join(struct.pack("<3f", *p) for p in pts)


def helix(n, r=1.0, pitch=0.5):
    return [(r * math.cos(0.7 * i), r * math.sin(0.7 * i), pitch * 0.1 * i) for i in range(n)]


def ring(n, r=2.0):
    return [(r * math.cos(2 * math.pi * i / n), 0.0, r * math.sin(2 * math.pi * i / n)) for i in range(n)]


def build(curves, up=1, **kw):
    total = sum(len(p) for p, _ in curves)
    return header(len(curves), total, up=up, **kw) + b"".join(curve(p, c) for p, c in curves)


def main():
    os.makedirs(OUT, exist_ok=True)
    files = {}
    files["valid-open.bcc"] = build([(helix(12), False)])
    files["valid-closed-zup.bcc"] = build([(ring(8), True)], up=2)
    files["valid-mixed.bcc"] = build([(helix(5), False), (ring(6), True), (helix(2), False)])
    # 3 closed points plus a repeated closing point (dropped by the reader).
    files["valid-repeated-closing-point.bcc"] = build([(ring(3) + [ring(3)[0]], True)])
    good = build([(helix(6), False), (ring(5), True)])
    files["bad-truncated.bcc"] = good[:-7]
    files["bad-trailing.bcc"] = good + b"\0\0\0"
    files["bad-signature.bcc"] = b"BCX" + good[3:]
    files["bad-curve-type.bcc"] = good[:4] + b"PT" + good[6:]
    files["bad-huge-counts.bcc"] = good[:8] + struct.pack("<QQ", 2**64 - 1, 2**63) + good[24:]
    files["bad-point-sum.bcc"] = good[:16] + struct.pack("<Q", 10) + good[24:] + b"\0" * 12
    nan = bytearray(good)
    nan[64 + 4 + 4:64 + 4 + 8] = struct.pack("<f", float("nan"))
    files["bad-nan.bcc"] = bytes(nan)
    files["bad-int32-min.bcc"] = header(1, 2) + struct.pack("<i", -2**31) + b"\0" * 24
    files["bad-coincident.bcc"] = build([([(0, 0, 0), (1, 0, 0), (1, 0, 0)], False)])
    files["bad-short-closed.bcc"] = build([([(0, 0, 0), (1, 0, 0)], True)])
    files["bad-header-only.bcc"] = good[:40]
    for name, data in sorted(files.items()):
        assert len(data) < 4096, name
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
    print(f"wrote {len(files)} files to {os.path.normpath(OUT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
