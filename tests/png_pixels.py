#!/usr/bin/env python3
"""png_pixels.py PNG X Y [X Y ...] - print "R G B" of each pixel (column X, row Y from the top)
of an 8-bit RGB or RGBA, non-interlaced PNG (what PLplot's pngcairo writes).  Plain python3
(zlib): a helper of tests/test_terrain_report.c, which checks the colours of map cells."""
import struct
import sys
import zlib


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else b if pb <= pc else c


def decode(path):
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
    pos, idat = 8, b''
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            w, h, depth, ctype, _, _, interlace = struct.unpack('>IIBBBBB', body)
            assert depth == 8 and ctype in (2, 6) and interlace == 0, 'unsupported PNG'
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    bpp = 3 if ctype == 2 else 4
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for r in range(h):
        f, line = raw[r * (stride + 1)], bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            line[i] = (line[i] + (0, a, b, (a + b) // 2, paeth(a, b, c))[f]) & 255
        rows.append(line)
        prev = line
    return rows, bpp


def main():
    rows, bpp = decode(sys.argv[1])
    xy = [int(v) for v in sys.argv[2:]]
    for k in range(0, len(xy), 2):
        x, y = xy[k], xy[k + 1]
        print(*rows[y][x * bpp:x * bpp + 3])


if __name__ == '__main__':
    main()
