#!/usr/bin/env python3
"""An outside renderer for `surftrace compare`: the van der Waals surface (the union of the
atoms' spheres) ray-cast with numpy, sharing no code with SurfTrace.

It knows only what any GL program knows: the atoms (`surftrace info FILE --xyzr atoms.xyzr`)
and a camera's width, height, view matrix and projection matrix (16 numbers each, column-major,
from `surftrace render ... --camera-out cam.json` or written by you). It casts one ray per pixel
centre through inverse(P·V) and writes what a GL renderer would read back with glReadPixels:

  DEPTH.pfm   window depth in [0, 1] (glDepthRange 0..1), background 1.0, rows bottom first
  --normal N  view-space unit normals (x right, y up, z towards the eye), same rows

PFM stores its bottom row first, so glReadPixels' buffer is written as it is. Check it with
  surftrace compare DEPTH.pfm reference.exr --depth-convention window --test-origin bottom-left \\
      --test-normal N --normal-space view
"""
import argparse
import json
import os
import subprocess
import sys


def import_numpy():
    """numpy, from this interpreter or, when it has none (a pyenv or venv python3 first on PATH),
    by running this script again under /usr/bin/python3, where Debian's python3-numpy installs:
    the interpreter SurfTrace's own tests choose first (cmake/OraclePython.cmake)."""
    try:
        import numpy
        return numpy
    except ModuleNotFoundError:
        pass
    system = "/usr/bin/python3"
    retried = os.environ.get("SURFTRACE_EXAMPLE_RETRIED") == "1"
    if not retried and os.access(system, os.X_OK) and \
            subprocess.run([system, "-c", "import numpy"], capture_output=True).returncode == 0:
        print(f"{os.path.basename(__file__)}: this python3 ({sys.executable}) cannot import numpy; running again "
              f"under {system}", file=sys.stderr)
        os.environ["SURFTRACE_EXAMPLE_RETRIED"] = "1"
        os.execv(system, [system, os.path.abspath(__file__)] + sys.argv[1:])
    sys.exit(f"{os.path.basename(__file__)}: needs numpy, which neither {sys.executable} nor {system} imports: "
             "install it (Debian: apt-get install python3-numpy; else pip install numpy) or run this script with "
             "a python3 that has it")


np = import_numpy()


def read_camera(path):
    cam = json.load(open(path))
    # Column-major, as glm and glUniformMatrix4fv keep them: element (row r, column c) is [4c + r].
    view = np.array(cam["view_matrix"], dtype=np.float64).reshape(4, 4).T
    proj = np.array(cam["projection_matrix"], dtype=np.float64).reshape(4, 4).T
    return int(cam["width"]), int(cam["height"]), view, proj


def read_atoms(path):
    atoms = np.loadtxt(path, dtype=np.float64, ndmin=2)
    return atoms[:, :3], atoms[:, 3]


def pixel_rays(width, height, view, proj):
    """Rays through pixel centres, rows bottom first (glReadPixels' order): each starts on the
    near plane and runs to the far plane, so perspective and orthographic cameras alike work."""
    ndc_x = 2.0 * (np.arange(width) + 0.5) / width - 1.0
    ndc_y = 2.0 * (np.arange(height) + 0.5) / height - 1.0  # row 0 is the bottom: ndc y = -1
    x, y = np.meshgrid(ndc_x, ndc_y)
    inverse = np.linalg.inv(proj @ view)

    def unproject(ndc_z):
        clip = np.stack([x, y, np.full_like(x, ndc_z), np.ones_like(x)], axis=-1) @ inverse.T
        return clip[..., :3] / clip[..., 3:]

    start, end = unproject(-1.0), unproject(1.0)
    direction = end - start
    direction /= np.linalg.norm(direction, axis=-1, keepdims=True)
    return start, direction


def cast(start, direction, centres, radii):
    """Nearest sphere hit per ray (distance from the start, +inf on a miss) and its atom."""
    nearest = np.full(start.shape[:-1], np.inf)
    atom = np.full(start.shape[:-1], -1)
    for i, (c, r) in enumerate(zip(centres, radii)):
        oc = c - start
        along = np.einsum("...k,...k->...", oc, direction)
        # Distance of the centre from the ray, not b² - 4ac: no cancellation for far spheres.
        perp2 = np.einsum("...k,...k->...", oc, oc) - along * along
        half = np.sqrt(np.maximum(r * r - perp2, 0.0))
        t = np.where(perp2 <= r * r, along - half, np.inf)
        t = np.where(t >= 0.0, t, np.inf)
        closer = t < nearest
        nearest[closer] = t[closer]
        atom[closer] = i
    return nearest, atom


def write_pfm(path, image):
    """Float32 little-endian PFM; the array's row 0 is the file's first (bottom) row."""
    image = np.ascontiguousarray(image, dtype="<f4")
    height, width = image.shape[:2]
    magic = b"PF" if image.ndim == 3 else b"Pf"
    with open(path, "wb") as f:
        f.write(b"%s\n%d %d\n-1.0\n" % (magic, width, height))
        f.write(image.tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("atoms", help="x y z r per line (surftrace info FILE --xyzr atoms.xyzr)")
    parser.add_argument("camera", help="JSON with width, height, view_matrix, projection_matrix")
    parser.add_argument("depth", help="window-depth PFM to write")
    parser.add_argument("--normal", help="view-space normal PFM to write")
    args = parser.parse_args()

    width, height, view, proj = read_camera(args.camera)
    centres, radii = read_atoms(args.atoms)
    start, direction = pixel_rays(width, height, view, proj)
    t, atom = cast(start, direction, centres, radii)
    hit = np.isfinite(t)
    point = start + np.where(hit, t, 0.0)[..., None] * direction

    # Window depth, as the GL pipeline makes it: clip = P·V·x, ndc z = clip z / clip w, d = (ndc z + 1) / 2.
    clip = np.concatenate([point, np.ones_like(t)[..., None]], axis=-1) @ (proj @ view).T
    depth = np.where(hit, 0.5 * clip[..., 2] / clip[..., 3] + 0.5, 1.0)
    write_pfm(args.depth, depth)

    if args.normal:
        normal = np.zeros_like(point)
        normal[hit] = (point[hit] - centres[atom[hit]]) / radii[atom[hit], None]
        normal = normal @ view[:3, :3].T  # world to view: the view matrix's rotation
        write_pfm(args.normal, normal)
    print(f"{args.depth}: {width}x{height}, {int(hit.sum())} pixels hit {len(radii)} atoms")


if __name__ == "__main__":
    main()
