#!/usr/bin/env python3
"""SES area and volume along a trajectory, with MDAnalysis, plotted with matplotlib.

MDAnalysis reads the trajectory; a `surftrace.Updater` takes each frame's coordinates straight
from `ag.positions` and rebuilds only the patches near atoms that moved (the surface equals a
full rebuild bit for bit). Prints the area and volume of every frame and plots both against time.

Run it from the repository root (AdK's closed-to-open transition, 98 frames, 3341 atoms):

    PYTHONPATH=build/ci/python /usr/bin/python3 examples/python/adk_trajectory.py \\
        tests/data/trajectories/adk_dims/adk.psf.gz tests/data/trajectories/adk_dims/adk_dims.dcd adk_ses.png
"""
import argparse

import matplotlib
matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt
import MDAnalysis as mda

import surftrace


def size(text):
    width, height = (int(v) for v in text.lower().split("x"))
    return width, height


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("topology", help="PSF, GRO, PDB, mmCIF")
    parser.add_argument("trajectory", help="DCD, XTC, ...")
    parser.add_argument("png", help="the plot to write")
    parser.add_argument("--frames", type=int, help="only the first N frames (default: all)")
    parser.add_argument("--probe", type=float, default=1.4, help="probe radius in Å (default 1.4)")
    parser.add_argument("--size", type=size, default=(800, 500), help="the plot's size in pixels (default 800x500)")
    args = parser.parse_args()

    # SurfTrace's atoms (its radii; water left out) at the first frame, and the same atoms in
    # MDAnalysis: mol.indices are their indices in the topology, as MDAnalysis counts them.
    mol = surftrace.read(args.topology, trajectory=args.trajectory)
    u = mda.Universe(args.topology, args.trajectory)
    ag = u.atoms[mol.indices]
    upd = surftrace.Updater(mol, surface="ses", probe=args.probe)

    times, areas, volumes = [], [], []
    print("frame  time_ps  ses_area_A2  ses_volume_A3")
    for ts in u.trajectory[:args.frames]:
        surface = upd.update(ag.positions)
        times.append(ts.time)
        areas.append(surface.area)
        volumes.append(surface.volume)
        print(ts.frame, f"{ts.time:.3f}", repr(surface.area), repr(surface.volume))  # repr: every digit

    width, height = args.size
    dpi = 100
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(width / dpi, height / dpi), dpi=dpi)
    top.plot(times, areas)
    top.set_ylabel("SES area (Å²)")
    bottom.plot(times, volumes, color="tab:orange")
    bottom.set_ylabel("SES volume (Å³)")
    bottom.set_xlabel("time (ps)")
    fig.suptitle(f"{args.trajectory.split('/')[-1]}: {len(ag)} atoms, probe {args.probe} Å")
    fig.savefig(args.png, dpi=dpi)
    print(f"wrote {args.png} ({width}x{height})")


if __name__ == "__main__":
    main()
