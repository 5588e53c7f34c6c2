#!/usr/bin/env python3
"""Checks that a PNG screenshot is not blank: it must have at least --min-colours distinct
colours and at least --min-ink of its pixels differing from the most common colour.

Only the standard library (zlib): 8-bit greyscale, RGB, grey+alpha and RGBA, not interlaced,
which is what Chromium writes. Exits 1 (with the counts) when the image looks blank."""

import argparse
import struct
import sys
import zlib
from collections import Counter

CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}


def read_png(path):
    """Returns (width, height, channels, rows of bytes)."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace:
        sys.exit(f"{path}: unsupported PNG (depth {depth}, colour type {colour}, interlace {interlace})")
    return width, height, CHANNELS[colour], unfilter(zlib.decompress(idat), width, height, CHANNELS[colour])


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def unfilter(raw, width, height, bpp):
    """Undoes the PNG row filters (none, sub, up, average, Paeth)."""
    stride = width * bpp
    rows, prev, pos = [], bytearray(stride), 0
    for _ in range(height):
        kind, line = raw[pos], bytearray(raw[pos + 1 : pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):
            left = line[i - bpp] if i >= bpp else 0
            up = prev[i]
            corner = prev[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                line[i] = (line[i] + paeth(left, up, corner)) & 0xFF
        rows.append(bytes(line))
        prev = line
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("png")
    ap.add_argument("--min-colours", type=int, default=16)
    ap.add_argument("--min-ink", type=float, default=0.01)
    a = ap.parse_args()
    width, height, bpp, rows = read_png(a.png)
    counts = Counter()
    for row in rows:
        for x in range(0, len(row), bpp):
            counts[row[x : x + bpp]] += 1
    total = width * height
    background = counts.most_common(1)[0][1]
    ink = 1 - background / total
    print(f"{a.png}: {width}x{height}, {len(counts)} distinct colours, {ink:.1%} not background")
    if len(counts) < a.min_colours or ink < a.min_ink:
        print(f"error: {a.png} looks blank (want at least {a.min_colours} colours and {a.min_ink:.0%} ink)", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
