#!/usr/bin/env python3
"""pngtool.py - the CLI tests' own PNG and GIF reader/writer (zlib + struct,
no PIL), independent of the library, so the pictures bvox writes are checked
against a second implementation of the formats.

  pngtool.py write OUT.png W H V1,V2,...   8-bit gray PNG, row by row
  pngtool.py read IN.png                   JSON: width, height, channels,
                                           bits, rows (lists of samples)
  pngtool.py gif IN.gif                    JSON: version, width, height,
                                           frames, loops (NETSCAPE2.0 block)
"""
import json
import struct
import sys
import zlib


def write_png(path, w, h, values):
    raw = b"".join(b"\x00" + bytes(values[y * w:(y + 1) * w]) for y in range(h))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw)))
        f.write(chunk(b"IEND", b""))


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, depth, ctype, _, _, interlace = hdr
    assert interlace == 0 and depth in (8, 16) and ctype in (0, 2, 6), hdr
    ch = {0: 1, 2: 3, 6: 4}[ctype]  # 6: RGBA (render --background transparent)
    bpp = ch * depth // 8
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev, p = [], bytearray(stride), 0
    for _ in range(h):
        f, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        rows.append(bytes(line))
        prev = line
    if depth == 16:
        rows = [[struct.unpack(">H", r[i:i + 2])[0] for i in range(0, len(r), 2)] for r in rows]
    else:
        rows = [list(r) for r in rows]
    return {"width": w, "height": h, "channels": ch, "bits": depth, "rows": rows}


def read_gif(path):
    d = open(path, "rb").read()
    version = d[:6].decode("ascii")
    w, h, flags = struct.unpack("<HHB", d[6:11])
    pos = 13 + (3 * 2 ** ((flags & 7) + 1) if flags & 0x80 else 0)
    frames, loops = 0, False

    def skip_blocks(pos):
        while d[pos]:
            pos += d[pos] + 1
        return pos + 1

    while d[pos] != 0x3B:
        if d[pos] == 0x21:
            if d[pos + 1] == 0xFF and d[pos + 3:pos + 14] == b"NETSCAPE2.0":
                loops = True
            pos = skip_blocks(pos + 2)
        elif d[pos] == 0x2C:
            frames += 1
            lflags = d[pos + 9]
            pos += 10 + (3 * 2 ** ((lflags & 7) + 1) if lflags & 0x80 else 0)
            pos = skip_blocks(pos + 1)  # LZW minimum code size, then the data
        else:
            raise ValueError("bad GIF block 0x%02x at %d" % (d[pos], pos))
    return {"version": version, "width": w, "height": h, "frames": frames, "loops": loops}


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "write":
        write_png(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]),
                  [int(v) for v in sys.argv[5].split(",")])
    elif cmd == "read":
        print(json.dumps(read_png(sys.argv[2])))
    elif cmd == "gif":
        print(json.dumps(read_gif(sys.argv[2])))
    else:
        sys.exit("unknown command " + cmd)
