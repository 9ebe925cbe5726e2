#!/usr/bin/env python3
"""Test oracle: the element MDAnalysis guesses from each atom name of a topology.

    python3 mda_elements.py TOPOLOGY

MDAnalysis (Debian's python3-mdanalysis, test-only) parses TOPOLOGY (GRO, PSF; told by the
extension) with its own parser and prints, per atom in file order, tab-separated:

    index  resname  name  guess

index is the 0-based position in the file, guess what
MDAnalysis.topology.guessers.guess_atom_element answers for the name, upper case as
MDAnalysis writes it ("CL", "R" for "Ru1", "DUMMY" for "MW").

Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported.
"""
import sys
import warnings


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import MDAnalysis
        from MDAnalysis.topology.guessers import guess_atom_element
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_elements.py: cannot import MDAnalysis ({e}); install python3-mdanalysis",
              file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")
    u = MDAnalysis.Universe(sys.argv[1], topology_format=None)
    for index, atom in enumerate(u.atoms):
        print(f"{index}\t{atom.resname}\t{atom.name}\t{guess_atom_element(atom.name)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
