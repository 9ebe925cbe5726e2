"""Colour-map oracle: matplotlib's own colormaps, for the numbers in a file.

usage: mpl_colormap.py MAP FILE
FILE holds one number t per line; prints "r g b" (matplotlib.colormaps[MAP](t), floats, repr
precision) per line, in order. Shares no code with SurfTrace: the colours are matplotlib's.
"""
import sys

import matplotlib
import numpy as np

name, path = sys.argv[1], sys.argv[2]
t = np.array([float(line) for line in open(path) if line.strip()], dtype=float)
rgba = matplotlib.colormaps[name](t)
for r, g, b, _ in rgba:
    print(repr(float(r)), repr(float(g)), repr(float(b)))
