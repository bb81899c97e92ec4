#!/usr/bin/env python3
"""Counts pixels of a kind in a region of an 8-bit RGB PNG (the editor's screenshots), with the
standard library only.

Usage: png_pixels.py FILE.png KIND X0 Y0 X1 Y1
KIND: orange (the Fox's coat: red over green over blue, each by 40) or dark (every channel
below 22: the floor in shadow; the unlit floor and background are about 30). Every second pixel
of every second row is looked at; prints the count.
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
            if depth != 8 or color != 2:
                sys.exit(f"{path}: expected 8-bit RGB, got depth {depth} colour type {color}")
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride = zlib.decompress(idat), width * 3
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b = prev[i]
            c = prev[i - 3] if i >= 3 else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + ((a + b) >> 1)) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, rows


KINDS = {
    "orange": lambda r, g, b: r > 150 and r > g + 40 and g > b + 40,
    "dark": lambda r, g, b: max(r, g, b) < 22,
}


def main():
    path, kind = sys.argv[1], sys.argv[2]
    x0, y0, x1, y1 = (int(v) for v in sys.argv[3:7])
    width, height, rows = read_png(path)
    if not (0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height):
        sys.exit(f"{path}: region outside the {width}x{height} image")
    test = KINDS[kind]
    count = sum(1 for y in range(y0, y1, 2) for x in range(x0, x1, 2)
                if test(rows[y][3 * x], rows[y][3 * x + 1], rows[y][3 * x + 2]))
    print(count)


if __name__ == "__main__":
    main()
