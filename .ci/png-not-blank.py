"""Fails unless a PNG (8-bit RGB or RGBA, not interlaced) shows something: at least 1% of
its pixels differ from its most common colour. Standard library only."""

import struct
import sys
import zlib
from collections import Counter


def pixels(path: str) -> tuple[int, int, int, list[bytes]]:
    with open(path, "rb") as file:
        data = file.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    header: tuple[int, ...] | None = None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    assert header is not None, "no IHDR chunk"
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, f"unsupported PNG {header}"
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    previous = bytearray(stride)
    rows: list[bytes] = []
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1 : start + 1 + stride])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                predicted = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[i] = (line[i] + predicted) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, channels, rows


width, height, channels, rows = pixels(sys.argv[1])
counts: Counter[bytes] = Counter()
for row in rows[:: max(1, height // 400)]:
    for x in range(0, len(row), channels * 2):
        counts[row[x : x + 3]] += 1
total = sum(counts.values())
share = 1 - counts.most_common(1)[0][1] / total
if share < 0.01:
    sys.exit(f"{sys.argv[1]}: blank ({share:.2%} of pixels differ from the background)")
print(f"{sys.argv[1]}: {width}x{height}, {share:.1%} of sampled pixels are not background")
