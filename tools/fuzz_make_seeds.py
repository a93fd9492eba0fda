#!/usr/bin/python3
"""Writes the binary seed inputs of tests/fuzz/corpus (PNG, PLY, vocabulary) with the standard
library only, so the seeds are reproducible and tiny. Text seeds are committed as they are.
Usage: /usr/bin/python3 tools/fuzz_make_seeds.py   (from the repository root)"""
import os
import struct
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fuzz", "corpus")


def png(width, height, bit_depth, colour_type, rows):
    """colour_type 0 = grey, 2 = RGB; rows = list of raw row bytes (without the filter byte)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def write(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def main():
    w, h = 4, 3
    depth16 = [struct.pack(">4H", *[1000 + 250 * (u + v) if (u + v) % 3 else 0 for u in range(w)]) for v in range(h)]
    write("depth_png", "depth16_4x3.png", png(w, h, 16, 0, depth16))
    write("depth_png", "depth8_4x3.png", png(w, h, 8, 0, [bytes([10, 20, 30, 40])] * h))
    write("depth_png", "rgb8_2x2.png", png(2, 2, 8, 2, [bytes(range(6))] * 2))
    labels8 = [bytes([(u + v) % 16 for u in range(w)]) for v in range(h)]
    write("label_png", "labels8_4x3.png", png(w, h, 8, 0, labels8))
    write("label_png", "labels16_4x3.png", png(w, h, 16, 0, [struct.pack(">4H", 1, 2, 300, 15)] * h))
    write("label_png", "rgb8_4x3.png", png(w, h, 8, 2, [bytes(range(12))] * h))

    props = ("ply\nformat binary_little_endian 1.0\ncomment written by s3m\nelement vertex {}\n"
             "property float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\n{}end_header\n")
    sem = "property ushort label\nproperty float confidence\n"
    pts = [(1.5, -2.0, 3.25, 255, 0, 7), (0.0, 0.0, 0.0, 1, 2, 3)]
    body = b"".join(struct.pack("<3f3B", *p) for p in pts)
    write("ply", "plain.ply", props.format(2, "").encode() + body)
    body = b"".join(struct.pack("<3f3BHf", *p, 12, 0.75) for p in pts)
    write("ply", "semantic.ply", props.format(2, sem).encode() + body)

    # Vocabulary v1: root + 2 leaves, branching 2, 1 level (see src/s3m/features/bow_io.cpp).
    out = b"S3MVOCAB" + struct.pack("<5I", 1, 2, 1, 1, 3)
    for parent, weight, fill in ((0, 0.0, 0), (0, 0.5, 0x0F), (0, 0.7, 0xF0)):
        out += struct.pack("<If", parent, weight) + bytes([fill]) * 32
    h64 = 1469598103934665603
    for c in out:
        h64 = ((h64 ^ c) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    write("vocabulary", "tiny_k2_l1.bin", out + struct.pack("<Q", h64))
    write("vocabulary", "truncated.bin", out[:40])


if __name__ == "__main__":
    main()
