#!/usr/bin/env python3
"""Test oracle: the atoms as MDAnalysis reads them, for the reader and `info --atoms` tests.

    python3 mda_atoms.py TOPOLOGY

MDAnalysis (Debian's python3-mdanalysis, test-only) reads TOPOLOGY (PDB, GRO, PSF, PQR; told by
the extension, gzip allowed), every record of the first model, alternate locations included,
and prints one tab-separated line per atom in file order:

    index  serial  name  resname  chainID  segid  resid  icode  altLoc

`-` stands for a field that is empty or that the format does not have (GRO and PSF have no
chainID, serial or altLoc).

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
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_atoms.py: cannot import MDAnalysis ({e}); install python3-mdanalysis", file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")
    u = MDAnalysis.Universe(sys.argv[1])

    def field(atom, name):
        value = getattr(atom, name, None)
        if value is None:
            return "-"
        value = str(value)
        return value if value.strip() else "-"

    for atom in u.atoms:
        print("\t".join([str(atom.index), field(atom, "id"), field(atom, "name"), field(atom, "resname"),
                         field(atom, "chainID"), field(atom, "segid"), str(atom.resid), field(atom, "icode"),
                         field(atom, "altLoc")]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
