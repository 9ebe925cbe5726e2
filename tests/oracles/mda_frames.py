#!/usr/bin/env python3
"""Test oracle: a trajectory's frames as MDAnalysis reads them, dumped for the C++ tests.

    python3 mda_frames.py TRAJECTORY OUT.bin [FORMAT]

MDAnalysis (Debian's python3-mdanalysis, test-only) opens TRAJECTORY with its own reader for
the format (told by the extension, or FORMAT: DCD, XTC, GRO, XYZ, PDB), without a topology,
and OUT.bin receives, little-endian:

    int64 atoms, int64 frames
    per frame: float64 time, int64 has_cell, float64[6] cell (a, b, c, alpha, beta, gamma),
               float32[atoms * 3] positions (Å, as MDAnalysis holds them)

Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported, so a test can
say what to install rather than fail obscurely.
"""
import struct
import sys
import warnings


def main() -> int:
    if len(sys.argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    path, out = sys.argv[1], sys.argv[2]
    fmt = sys.argv[3] if len(sys.argv) == 4 else None
    try:
        import numpy as np
        from MDAnalysis.coordinates.core import get_reader_for
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_frames.py: cannot import MDAnalysis ({e}); install python3-mdanalysis", file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")
    reader_class = get_reader_for(path, format=fmt)
    reader = reader_class(path)
    with open(out, "wb") as f:
        f.write(struct.pack("<qq", reader.n_atoms, reader.n_frames))
        for ts in reader:
            dims = ts.dimensions
            has_cell = dims is not None and bool(np.any(dims[:3] != 0))
            cell = [float(x) for x in dims] if has_cell else [0.0] * 6
            f.write(struct.pack("<dq6d", float(ts.time), int(has_cell), *cell))
            f.write(np.ascontiguousarray(ts.positions, dtype="<f4").tobytes())
    reader.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
