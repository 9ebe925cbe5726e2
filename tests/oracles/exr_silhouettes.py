"""Silhouettes oracle: the lines `surftrace render --silhouettes --exr` drew lie along the depth
jumps of the EXR's own buffers, recomputed with numpy.

Reads the EXR with a small reader of its own (OpenEXR scanline files, ZIP/ZIPS or no
compression, 32-bit channels: what SurfTrace writes), sharing no code with SurfTrace.

Definition (README, "Image-space effects"): an edge pixel is a pixel p whose centre ray hits
(patch.kind != 0) with one of its 8 neighbours a miss, or deeper in view depth by more than
JUMP Å: depth.z(q) - depth.z(p) > JUMP. The line is a band WIDTH x height pixels wide inside the
jump, drawn over the colour with its coverage c: colour = c * line + (1 - c) * plain.

The coverage of every pixel is recovered from the image with lines and the PLAIN one without
(same options, no --silhouettes) through the line colour's channel farthest from the plain
colour. Checked: every edge pixel next to the background is at least half covered when the
band is 1.92 px wide or more (the jump lies within √2 px of the pixel's centre), covered at all
when narrower; and no pixel farther than the band's width and 1.5 px from every edge pixel is
covered. A jump between two hits may be one surface turning away near its rim, which the
renderer does not line: those edge pixels only bound where lines may be.

usage: exr_silhouettes.py IMAGE.exr PLAIN.exr WIDTH JUMP R,G,B
prints "edge pixels N, covered pixels M, mismatches K"; exit 0 when K == 0, 1 otherwise.
"""
import struct
import sys
import zlib

import numpy as np


def read_exr(path):
    data = open(path, "rb").read()
    magic, version = struct.unpack_from("<ii", data, 0)
    if magic != 20000630 or (version & 0xFF) != 2 or version & 0x1200:
        raise SystemExit(f"{path}: not a single-part scanline OpenEXR file")
    pos, header = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        pos = end + 1
        end = data.index(b"\0", pos)
        kind = data[pos:end].decode()
        pos = end + 1
        (size,) = struct.unpack_from("<i", data, pos)
        pos += 4
        header[name] = (kind, data[pos:pos + size])
        pos += size
    pos += 1
    channels, raw = [], header["channels"][1]
    i = 0
    while raw[i] != 0:
        end = raw.index(b"\0", i)
        name = raw[i:end].decode()
        (ptype,) = struct.unpack_from("<i", raw, end + 1)
        channels.append((name, ptype))  # 0 uint, 1 half, 2 float
        i = end + 1 + 16
    if any(t == 1 for _, t in channels):
        raise SystemExit(f"{path}: half channels are not read by this oracle")
    xmin, ymin, xmax, ymax = struct.unpack("<iiii", header["dataWindow"][1])
    width, height = xmax - xmin + 1, ymax - ymin + 1
    compression = header["compression"][1][0]
    lines_per_chunk = {0: 1, 2: 1, 3: 16}.get(compression)
    if lines_per_chunk is None:
        raise SystemExit(f"{path}: compression {compression} is not read by this oracle")
    chunks = (height + lines_per_chunk - 1) // lines_per_chunk
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    row_bytes = 4 * width * len(channels)
    image = bytearray(row_bytes * height)
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        block = data[offset + 8:offset + 8 + size]
        lines = min(lines_per_chunk, ymax + 1 - y)
        expected = row_bytes * lines
        if compression != 0 and size < expected:
            t = np.frombuffer(zlib.decompress(block), dtype=np.uint8).astype(np.int64)
            # Undo the predictor, t[i] = t[i-1] + t[i] - 128 (mod 256), then the interleave.
            t = ((np.cumsum(t - 128) + 128) % 256).astype(np.uint8)
            half = (len(t) + 1) // 2
            out = np.empty_like(t)
            out[0::2], out[1::2] = t[:half], t[half:]
            block = out.tobytes()
        image[(y - ymin) * row_bytes:(y - ymin + lines) * row_bytes] = block
    rows = np.frombuffer(bytes(image), dtype=np.uint8).reshape(height, len(channels), width * 4)
    result = {}
    for k, (name, ptype) in enumerate(channels):
        result[name] = rows[:, k, :].copy().view("<u4" if ptype == 0 else "<f4").reshape(height, width)
    return result


def main():
    path, plain_path, width, jump = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    color = np.array([float(c) for c in sys.argv[5].split(",")], dtype=np.float64)
    exr, plain = read_exr(path), read_exr(plain_path)
    h, w = exr["patch.kind"].shape
    width_px = width * h
    hit = exr["patch.kind"] != 0
    z = np.where(hit, exr["depth.z"].astype(np.float64), np.inf)
    # The largest depth among the 8 neighbours (misses at +inf), the image's border not counted.
    padded = np.full((h + 2, w + 2), -np.inf)
    padded[1:-1, 1:-1] = z
    deepest = np.full((h, w), -np.inf)
    for dy in range(3):
        for dx in range(3):
            if dy != 1 or dx != 1:
                deepest = np.maximum(deepest, padded[dy:dy + h, dx:dx + w])
    with np.errstate(invalid="ignore"):  # inf - inf: NaN, not > jump
        edge = hit & (deepest - z > jump)
    outline = hit & np.isinf(deepest)  # a neighbour is background
    lined = np.stack([exr[c].astype(np.float64) for c in "RGB"], axis=-1)
    base = np.stack([plain[c].astype(np.float64) for c in "RGB"], axis=-1)
    # colour = c line + (1 - c) plain, solved in the channel where line and plain differ most.
    gap = color[None, None, :] - base
    k = np.argmax(np.abs(gap), axis=-1)[..., None]
    g = np.take_along_axis(gap, k, -1)[..., 0]
    d = np.take_along_axis(lined - base, k, -1)[..., 0]
    coverage = np.where(np.abs(g) > 0.05, d / np.where(np.abs(g) > 0.05, g, 1.0), 0.0)
    covered = coverage > 1e-3
    # Distance from every pixel to the nearest edge pixel (brute force over the edge pixels).
    ys, xs = np.nonzero(edge)
    gy, gx = np.mgrid[0:h, 0:w]
    nearest = np.full((h, w), np.inf)
    for y, x in zip(ys.tolist(), xs.tolist()):
        nearest = np.minimum(nearest, np.hypot(gx - x, gy - y))
    # Only the outline must be covered: a jump to a hit may be one surface turning away near
    # its rim, which the renderer does not line (its tangent plane carries on).
    uncovered_edges = outline & (coverage < (0.5 if width_px >= 1.92 else 0.0) + 1e-3)
    stray = covered & (nearest > width_px + 1.5)
    mismatch = int(np.count_nonzero(uncovered_edges) + np.count_nonzero(stray))
    print(f"edge pixels {int(edge.sum())}, covered pixels {int(covered.sum())}, partly covered "
          f"{int(np.count_nonzero(covered & (coverage < 0.95)))}, mismatches {mismatch}")
    for name, bad in (("outline pixels under half covered", uncovered_edges), ("covered far from any edge", stray)):
        if bad.any():
            by, bx = np.nonzero(bad)
            print(f"{name} (x, y):", list(zip(bx[:10].tolist(), by[:10].tolist())))
    return 0 if mismatch == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
