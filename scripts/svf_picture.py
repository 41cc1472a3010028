#!/usr/bin/env python3
"""svf_picture.py FILE OUT.png [SEGMENT] — one segment of a `fibertwin bake
segment-visibility` file as 004 Fig. 4: (a) the binary visibility image, (b)
the PCA-compressed SSDF (yellow +, blue -, +-1 rad), (c) its sign, (d) the sum
of SGs (grey, scaled to its maximum). Decodes the file itself (pure Python:
the format of bake/segment_visibility_bake.h, the axes of 004 §4.1c, pixel
directions of common/segment_visibility.h). Without SEGMENT: the segment whose
occluded fraction is the median of the first 400."""
import json, math, struct, sys, zlib


def read(path):
    data = open(path, "rb").read()
    nl = data.index(b"\n")
    h = json.loads(data[:nl])
    S, W, H, Q, C = h["segments"], h["width"], h["height"], h["axes"], h["components"]
    P = W * H
    at = nl + 1 + S * 32
    svf = struct.unpack_from("<%df" % (S * (1 + Q + C)), data, at)
    at += 4 * S * (1 + Q + C)
    mean = struct.unpack_from("<%df" % P, data, at)
    at += 4 * P
    basis = struct.unpack_from("<%df" % (C * P), data, at)
    at += 4 * C * P
    bb = (P + 7) // 8
    images = data[at:at + S * bb]
    return h, svf, mean, basis, images


def png(path, w, h, rgb):
    raw = b"".join(b"\x00" + bytes(rgb[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    h, svf, mean, basis, images = read(sys.argv[1])
    S, W, H, Q, C, lam = h["segments"], h["width"], h["height"], h["axes"], h["components"], h["lambda"]
    P, bb = W * H, (W * H + 7) // 8
    vis = lambda k, p: (images[k * bb + p // 8] >> (p % 8)) & 1
    if len(sys.argv) > 3:
        k = int(sys.argv[3])
    else:
        occ = sorted((sum(1 - vis(k, p) for p in range(P)), k) for k in range(min(S, 400)))
        k = occ[len(occ) // 2][1]
    row = svf[k * (1 + Q + C):(k + 1) * (1 + Q + C)]
    angle, w, a = row[0], row[1:1 + Q], row[1 + Q:]
    axes = []
    for q in range(1, Q + 1):
        z = 1 - (q - 1) / Q
        r = math.sqrt(max(0.0, 1 - z * z))
        phi = 4 * math.pi * q / (1 + math.sqrt(5)) + angle
        axes.append((r * math.cos(phi), r * math.sin(phi), z))
    M = 2 * math.pi * (1 - math.exp(-2 * lam)) / lam
    ssdf, sg = [], []
    for p in range(P):
        x, y = p % W, p // W
        t, ph = math.pi * (y + 0.5) / H, 2 * math.pi * (x + 0.5) / W - math.pi
        d = (math.sin(t) * math.cos(ph), math.sin(t) * math.sin(ph), math.cos(t))
        ssdf.append(mean[p] + sum(a[c] * basis[c * P + p] for c in range(C)))
        sg.append(sum(w[q] * math.exp(lam * (sum(d[i] * axes[q][i] for i in range(3)) - 1)) / M for q in range(Q)))
    peak = max(sg) or 1.0
    s, gap = max(1, 256 // W), 6
    pw, phh = W * s, H * s
    iw = 4 * pw + 3 * gap
    rgb = bytearray([255] * (iw * phh * 3))
    for panel in range(4):
        for Y in range(phh):
            for X in range(pw):
                p = (Y // s) * W + X // s
                if panel == 0:
                    c = (vis(k, p),) * 3
                elif panel == 1:
                    u = max(-1.0, min(1.0, ssdf[p]))
                    hi = (1.0, 0.85, 0.1) if u >= 0 else (0.1, 0.3, 1.0)
                    c = tuple(0.5 + (hi[i] - 0.5) * abs(u) for i in range(3))
                elif panel == 2:
                    c = (1.0 if ssdf[p] > 0 else 0.0,) * 3
                else:
                    c = (min(1.0, sg[p] / peak),) * 3
                o = (Y * iw + panel * (pw + gap) + X) * 3
                rgb[o:o + 3] = bytes(int(round(255 * v)) for v in c)
    png(sys.argv[2], iw, phh, rgb)
    print("segment %d of %d: %d of %d pixels occluded; %s" % (k, S, sum(1 - vis(k, p) for p in range(P)), P, sys.argv[2]))


main()
