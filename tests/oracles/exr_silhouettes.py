"""Silhouettes oracle: the pixels `surftrace render --silhouettes --exr` drew in the line colour
are exactly those at a depth jump, recomputed with numpy from the EXR's own buffers.

Reads the EXR with a small reader of its own (OpenEXR scanline files, ZIP/ZIPS or no
compression, 32-bit channels: what SurfTrace writes), sharing no code with SurfTrace.

Definition (README, "Image-space effects"): a pixel p whose centre ray hits (patch.kind != 0)
is on a silhouette when some pixel q with max(|qx - px|, |qy - py|) <= WIDTH inside the image
is a miss, or lies deeper in view depth by more than JUMP Å: depth.z(q) - depth.z(p) > JUMP.

usage: exr_silhouettes.py IMAGE.exr WIDTH JUMP R,G,B
prints "silhouette pixels N, line-coloured pixels M, mismatches K"; exit 0 when K == 0, 1 otherwise.
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


def window_max(z, r):
    """Max of z over the (2r+1)^2 window of every pixel, the window clipped to the image."""
    h, w = z.shape
    padded = np.full((h + 2 * r, w + 2 * r), -np.inf)
    padded[r:r + h, r:r + w] = z
    m = np.full((h, w), -np.inf)
    for dy in range(2 * r + 1):
        for dx in range(2 * r + 1):
            m = np.maximum(m, padded[dy:dy + h, dx:dx + w])
    return m


def main():
    path, width, jump = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    color = np.array([float(c) for c in sys.argv[4].split(",")], dtype=np.float32)
    exr = read_exr(path)
    hit = exr["patch.kind"] != 0
    z = np.where(hit, exr["depth.z"].astype(np.float64), np.inf)
    with np.errstate(invalid="ignore"):  # inf - inf at misses: NaN, not > jump
        silhouette = hit & (window_max(z, width) - z > jump)
    rgb = np.stack([exr["R"], exr["G"], exr["B"]], axis=-1)
    coloured = np.all(rgb == color, axis=-1)
    mismatch = int(np.count_nonzero(silhouette != coloured))
    print(f"silhouette pixels {int(silhouette.sum())}, line-coloured pixels {int(coloured.sum())}, mismatches {mismatch}")
    if mismatch:
        ys, xs = np.nonzero(silhouette != coloured)
        print("first mismatches (x, y):", list(zip(xs[:10].tolist(), ys[:10].tolist())))
    return 0 if mismatch == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
