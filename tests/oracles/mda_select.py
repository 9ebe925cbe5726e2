#!/usr/bin/env python3
"""Test oracle: the atoms MDAnalysis's select_atoms picks, for the C++ selection tests.

    python3 mda_select.py TOPOLOGY SELECTION...

MDAnalysis (Debian's python3-mdanalysis, test-only) reads TOPOLOGY (PSF, GRO, PDB; told by the
extension, gzip allowed) and prints its atom count on the first line, then one line per
SELECTION: the selected atoms' 0-based indices, ascending, separated by spaces (an empty line
when none).

SurfTrace's selections are MDAnalysis's with these words translated first (word by word):
    atom  -> bynum    (MDAnalysis's own `atom` means "atom SEGID RESID NAME")
    chain, chainID -> chainID where the topology has chain identifiers (PDB), else segid
             (a PSF has segments but no chains: surftrace's chain is its segid there)
    segid stays segid: surftrace reads segment ids as MDAnalysis does
    water -> resname H2O HOH ...  where this MDAnalysis has no `water` keyword (added in 2.9.0;
             the names are its WaterSelection.water_res)
    A, B  -> (A) or (B)   (commas: surftrace's union of whole expressions)

Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported, so a test can
say what to install rather than fail obscurely; 4 when MDAnalysis refuses a selection.
"""
import sys
import warnings

WATER_RES = ["H2O", "HOH", "OH2", "HHO", "OHH", "T3P", "T4P", "T5P", "SOL", "WAT", "TIP",
             "TIP2", "TIP3", "TIP4"]


def translate(selection: str, has_chain_ids: bool, has_water: bool) -> str:
    parts = []
    for part in selection.split(","):
        words = []
        for word in part.replace("(", " ( ").replace(")", " ) ").split():
            if word == "atom":
                word = "bynum"
            elif word in ("chain", "chainID", "chainid"):
                word = "chainID" if has_chain_ids else "segid"
            elif word == "water" and not has_water:
                word = "(resname " + " ".join(WATER_RES) + ")"
            words.append(word)
        parts.append(" ".join(words))
    return " or ".join(f"({p})" for p in parts) if len(parts) > 1 else parts[0]


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import MDAnalysis
        from MDAnalysis.core import selection as mda_selection
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mda_select.py: cannot import MDAnalysis ({e}); install python3-mdanalysis",
              file=sys.stderr)
        return 3
    warnings.simplefilter("ignore")
    u = MDAnalysis.Universe(sys.argv[1])
    has_chain_ids = hasattr(u.atoms, "chainIDs")
    has_water = "water" in mda_selection._SELECTIONDICT
    print(len(u.atoms))
    for selection in sys.argv[2:]:
        mda = translate(selection, has_chain_ids, has_water)
        try:
            picked = u.select_atoms(mda)
        except Exception as e:  # MDAnalysis says SelectionError, ValueError, NoDataError
            print(f"mda_select.py: MDAnalysis refuses {mda!r} (from {selection!r}): {e}",
                  file=sys.stderr)
            return 4
        print(" ".join(str(i) for i in sorted(picked.indices)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
