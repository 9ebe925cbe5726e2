#!/usr/bin/env python3
"""Validate a renderer's depth buffer held in numpy against SurfTrace's exact surface.

The renderer under test is a tiny numpy ray caster of the atoms' spheres (the van der Waals
surface), drawn with the camera of SurfTrace's reference image; `--error` adds a constant depth
error in Å to every pixel it hits, to see where the limits lie. `surftrace.compare` takes the
buffer as it is (no files), measures it in Å along the reference's rays and judges it.
Exit status: 0 when it passes, 2 when it fails, as `surftrace compare`.

Run it from the repository root:

    PYTHONPATH=build/ci/python /usr/bin/python3 examples/python/validate_depth.py \\
        tests/data/structures/1crn.pdb --error 0.5
"""
import argparse
import sys

import numpy as np

import surftrace


def cast_spheres(camera, width, height, centres, radii):
    """View-space depth (Å in front of the eye, +inf on a miss) of the nearest sphere through
    each pixel centre, rows top first, as a GL renderer using the camera's matrices would see it."""
    view, proj = np.asarray(camera.view_matrix), np.asarray(camera.projection_matrix)
    ndc_x = 2.0 * (np.arange(width) + 0.5) / width - 1.0
    ndc_y = 1.0 - 2.0 * (np.arange(height) + 0.5) / height  # row 0 is the top
    x, y = np.meshgrid(ndc_x, ndc_y)
    inverse = np.linalg.inv(proj @ view)

    def unproject(ndc_z):  # the pixel's point on the near (-1) or far (+1) plane, in world space
        clip = np.stack([x, y, np.full_like(x, ndc_z), np.ones_like(x)], axis=-1) @ inverse.T
        return clip[..., :3] / clip[..., 3:]

    start = unproject(-1.0)
    direction = unproject(1.0) - start
    direction /= np.linalg.norm(direction, axis=-1, keepdims=True)
    nearest = np.full((height, width), np.inf)
    for c, r in zip(centres, radii):
        oc = c - start
        along = np.einsum("...k,...k->...", oc, direction)
        # The centre's distance from the ray, not b² - 4ac: no cancellation for far spheres.
        perp2 = np.einsum("...k,...k->...", oc, oc) - along * along
        t = np.where(perp2 <= r * r, along - np.sqrt(np.maximum(r * r - perp2, 0.0)), np.inf)
        nearest = np.minimum(nearest, np.where(t >= 0.0, t, np.inf))
    hit = np.isfinite(nearest)
    point = start + np.where(hit, nearest, 0.0)[..., None] * direction
    view_z = -(point @ view[:3, :3].T + view[:3, 3])[..., 2]  # the eye looks down -z
    return np.where(hit, view_z, np.inf)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("structure", help="PDB, mmCIF, PQR, ... (gzipped too)")
    parser.add_argument("--error", type=float, default=0.0, help="depth error in Å added to every hit (default 0)")
    parser.add_argument("--size", type=int, default=128, help="image width and height in pixels (default 128)")
    args = parser.parse_args()

    mol = surftrace.read(args.structure)
    reference = surftrace.render(surftrace.vdw(mol), size=(args.size, args.size))

    depth = cast_spheres(reference.camera, args.size, args.size, mol.centres, mol.radii)
    depth[np.isfinite(depth)] += args.error

    report = surftrace.compare({"depth": depth}, reference, depth_convention="view-z", origin="top-left")
    d = report["depth"]
    print(f"depth error  median {d['median']:.3g}  p99 {d['p99']:.3g}  max {d['max']:.3g} Å "
          f"(p99 = {d['p99_relative']:.3g} of the scene size {d['scene_size']:.3g} Å)")
    print(f"coverage mismatch {report['coverage']['mismatch']} px")
    print(report["verdict"])  # "PASS (foreign, ...)", or "FAIL (...)" and the limits it broke
    return 0 if report["passed"] else 2


if __name__ == "__main__":
    sys.exit(main())
