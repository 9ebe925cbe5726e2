"""PyMOL's own SES, ray-traced at the same size, for the renderer benchmark's comparison.

Usage: pymol -cq bench/pymol_compare.py -- FILE [SIZE] [THREADS]
Prints the surface (mesh) build time and the ray-tracing time of one SIZE x SIZE frame.
PyMOL (Debian package `pymol`) is what users reach for on a server; it triangulates the
surface and ray-traces the triangles.
"""
import sys
import time

from pymol import cmd

path = sys.argv[1]
size = int(sys.argv[2]) if len(sys.argv) > 2 else 1024
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
cmd.set("max_threads", threads)
cmd.load(path, "m")
cmd.remove("solvent")
cmd.hide("everything")
cmd.show("surface")
cmd.set("solvent_radius", 1.4)
cmd.orient("m")
t0 = time.perf_counter()
cmd.ray(16, 16)  # forces the surface mesh; the tiny frame itself costs nothing
t1 = time.perf_counter()
cmd.ray(size, size)
t2 = time.perf_counter()
print(f"{path}: pymol surface {t1 - t0:.2f} s, ray {size}x{size} {t2 - t1:.2f} s ({threads} threads)")
