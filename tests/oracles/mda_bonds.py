#!/usr/bin/env python3
"""Test oracle: the bonds MDAnalysis finds in a PDB file.

    python3 mda_bonds.py guess FILE RADII TOLERANCE
    python3 mda_bonds.py conect FILE
    python3 mda_bonds.py structconn FILE.cif[.gz]

guess: MDAnalysis.topology.guessers.guess_bonds over the atoms of FILE's first model, each
atom's type set to its element (upper case) and vdwradii set to r + TOLERANCE/2 from RADII
("C=0.76,N=0.71,..."), fudge_factor 1: pairs with d < r_i + r_j + TOLERANCE (d >= 0.1 Å).
conect: the bonds MDAnalysis's PDB parser reads from FILE's CONECT records.
structconn: the covalent links (conn_type_id covale*, disulf; symmetry 1_555) of the mmCIF
_struct_conn loop, read as whitespace-separated tokens without MDAnalysis (it reads no
_struct_conn), one per line: "chain seq atom chain seq atom" (author chain and number).

Prints one bond per line, "i j" with 0-based atom indices in file order, i < j, sorted.
Exit status 3 (with a message on stderr) when MDAnalysis cannot be imported.
"""
import sys
import warnings


def struct_conn(path: str) -> int:
    import gzip
    import shlex
    text = (gzip.open if path.endswith(".gz") else open)(path, "rt").read().splitlines()
    tags, rows, i = [], [], 0
    while i < len(text):
        if text[i].strip() == "loop_" and i + 1 < len(text) and text[i + 1].startswith("_struct_conn."):
            i += 1
            while text[i].startswith("_struct_conn."):
                tags.append(text[i].split()[0][len("_struct_conn."):])
                i += 1
            tokens = []
            while i < len(text) and not text[i].startswith(("_", "loop_", "#")):
                tokens += shlex.split(text[i])
                i += 1
            rows = [tokens[k:k + len(tags)] for k in range(0, len(tokens), len(tags))]
            break
        i += 1
    col = {t: k for k, t in enumerate(tags)}
    for r in rows:
        kind = r[col["conn_type_id"]]
        if not (kind.startswith("covale") or kind == "disulf"):
            continue
        if r[col["ptnr1_symmetry"]] != "1_555" or r[col["ptnr2_symmetry"]] != "1_555":
            continue
        print(*(r[col[f"ptnr{p}_{what}"]] for p in (1, 2) for what in ("auth_asym_id", "auth_seq_id", "label_atom_id")))
    return 0


def main() -> int:
    if len(sys.argv) == 3 and sys.argv[1] == "structconn":
        return struct_conn(sys.argv[2])
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
