#!/usr/bin/python3
"""knit_strip.py OUT.png FRAME.png... — put frames of a `fibertwin knit --frames N`
sequence side by side into one PNG (docs/knit-rendering.md), each scaled to
--height pixels high, with a 4-pixel dark gap between them."""
import argparse

from PIL import Image


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("out")
    p.add_argument("frames", nargs="+")
    p.add_argument("--height", type=int, default=240)
    p.add_argument("--gap", type=int, default=4)
    a = p.parse_args()
    images = []
    for f in a.frames:
        im = Image.open(f).convert("RGB")
        w = round(im.width * a.height / im.height)
        images.append(im.resize((w, a.height), Image.LANCZOS))
    width = sum(im.width for im in images) + a.gap * (len(images) - 1)
    strip = Image.new("RGB", (width, a.height), (16, 16, 16))
    x = 0
    for im in images:
        strip.paste(im, (x, 0))
        x += im.width + a.gap
    strip.save(a.out, optimize=True)


if __name__ == "__main__":
    main()
