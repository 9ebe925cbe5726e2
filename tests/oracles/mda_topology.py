#!/usr/bin/env python3
"""Test oracle: a topology's atoms as MDAnalysis reads them, written for the C++ tests.

    python3 mda_topology.py TOPOLOGY OUT.tsv

MDAnalysis (Debian's python3-mdanalysis, test-only) parses TOPOLOGY (PSF, GRO; told by the
extension) with its own parser, and OUT.tsv receives a header line and then, per atom in file
order, tab-separated:

    id  name  resname  resid  segid  mass  mass_element

id is MDAnalysis's atom id, segid its segment id ('SYSTEM' where the format has none), mass
its mass (read from a PSF; guessed from the name for GRO) printed with repr() so that it
reads back exactly, and mass_element the element whose mass in MDAnalysis's own table
(MDAnalysis.topology.tables.masses) is nearest the atom's mass ('' for a mass of 0).

Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported, so a test can
say what to install rather than fail obscurely.
"""
import sys
import warnings


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    path, out = sys.argv[1], sys.argv[2]
    try:
        import MDAnalysis
        from MDAnalysis.topology import tables
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_topology.py: cannot import MDAnalysis ({e}); install python3-mdanalysis",
              file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")

    # The table keys are symbols in any case ("FE", "Fe", "NA" and "Na"), plus "DUMMY".
    by_element = {}
    for key, mass in tables.masses.items():
        symbol = key.capitalize()
        if key.upper() == "DUMMY" or mass <= 0:
            continue
        by_element.setdefault(symbol, float(mass))

    def nearest(mass: float) -> str:
        if not mass > 0:
            return ""
        return min(by_element.items(), key=lambda kv: abs(kv[1] - mass))[0]

    u = MDAnalysis.Universe(path, topology_format=None)
    atoms = u.atoms
    with open(out, "w", encoding="utf-8") as f:
        f.write("id\tname\tresname\tresid\tsegid\tmass\tmass_element\n")
        for atom in atoms:
            mass = float(atom.mass)
            f.write(f"{int(atom.id)}\t{atom.name}\t{atom.resname}\t{int(atom.resid)}\t"
                    f"{atom.segid}\t{mass!r}\t{nearest(mass)}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
