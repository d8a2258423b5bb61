#!/usr/bin/env python3
"""Is a PNG a picture? Decodes 8-bit non-interlaced RGB/RGBA/grey PNGs with zlib
alone (no imaging library) and requires some ink: at least min_ink of the
pixels not the background (the most common colour) and at least 4 colours.
Usage: png_check.py FILE [min_ink]"""
import struct, sys, zlib


def pixels(path):
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise SystemExit(f'{path}: not a PNG')
    pos, idat, hdr = 8, b'', None
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            hdr = struct.unpack('>IIBBBBB', body)
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or interlace:
        raise SystemExit(f'{path}: depth {depth}, interlace {interlace} not handled')
    bpp = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    raw, stride, prev, out = zlib.decompress(idat), w * bpp, bytearray(w * bpp), []
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out.extend(bytes(line[i:i + bpp]) for i in range(0, stride, bpp))
        prev = line
    return w, h, out


def main():
    path, min_ink = sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
    w, h, px = pixels(path)
    counts = {}
    for p in px:
        counts[p] = counts.get(p, 0) + 1
    background = max(counts.values())
    ink = 1 - background / len(px)
    if len(counts) < 4 or ink < min_ink:
        raise SystemExit(f'{path}: blank ({len(counts)} colours, {ink:.3%} ink)')
    print(f'{path}: {w}x{h}, {len(counts)} colours, {ink:.1%} ink')


main()
