#!/usr/bin/env python3
"""Test oracle: the bonds MDAnalysis finds in a PDB file.

    python3 mda_bonds.py guess FILE RADII TOLERANCE
    python3 mda_bonds.py conect FILE

guess: MDAnalysis.topology.guessers.guess_bonds over the atoms of FILE's first model, each
atom's type set to its element (upper case) and vdwradii set to r + TOLERANCE/2 from RADII
("C=0.76,N=0.71,..."), fudge_factor 1: pairs with d < r_i + r_j + TOLERANCE (d >= 0.1 Å).
conect: the bonds MDAnalysis's PDB parser reads from FILE's CONECT records.

Prints one bond per line, "i j" with 0-based atom indices in file order, i < j, sorted.
Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported.
"""
import sys
import warnings


def main() -> int:
    if len(sys.argv) not in (3, 5) or sys.argv[1] not in ("guess", "conect"):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import MDAnalysis
        from MDAnalysis.topology.guessers import guess_bonds
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_bonds.py: cannot import MDAnalysis ({e}); install python3-mdanalysis", file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")
    u = MDAnalysis.Universe(sys.argv[2])
    if sys.argv[1] == "conect":
        pairs = [tuple(sorted(int(a.index) for a in b)) for b in u.bonds]
    else:
        tolerance = float(sys.argv[4])
        radii = {k.upper(): float(v) + tolerance / 2
                 for k, v in (item.split("=") for item in sys.argv[3].split(","))}
        u.atoms.types = [e.upper() for e in u.atoms.elements]
        found = guess_bonds(u.atoms, u.atoms.positions.astype("float64"), vdwradii=radii, fudge_factor=1.0)
        pairs = [tuple(sorted((int(i), int(j)))) for i, j in found]
    for i, j in sorted(set(pairs)):
        print(i, j)
    return 0


if __name__ == "__main__":
    sys.exit(main())
