"""surftrace.read, surftrace.Molecule and Molecule.select: the atoms the command line reads,
numpy arrays in and out (checked, never a crash), and selections equal to MDAnalysis's."""
import gc
import importlib.util
import subprocess
import warnings

import numpy as np
import pytest

import surftrace


def xyzr_of(run_tool, path, tmp_path, *options):
    """The atoms every command uses (`surftrace info --xyzr`: shortest round-trip digits)."""
    out = tmp_path / "atoms.xyzr"
    run_tool("info", path, "--xyzr", out, *options)
    return np.loadtxt(out, ndmin=2)


@pytest.mark.parametrize("name, options, kwargs", [
    ("structures/1crn.pdb", [], {}),
    ("structures/1ubq.pdb.gz", ["--keep-water"], {"water": True}),
    ("structures/1ubq.pdb.gz", ["--no-hydrogens", "--chains", "A"], {"hydrogens": False, "chains": "A"}),
    ("structures/1v5a-3models.cif.gz", ["--model", "2"], {"model": 2}),
    ("formats/gro/ubiquitin.gro", [], {}),
    ("structures/1a0q.pdb.gz", ["--radii", "protor", "--keep-water"], {"radii": "protor", "water": True}),
])
def test_read_gives_the_atoms_of_the_command_line(data, run_tool, tmp_path, name, options, kwargs):
    mol = surftrace.read(data / name, **kwargs)
    want = xyzr_of(run_tool, data / name, tmp_path, *options)
    assert len(mol) == len(want)
    assert mol.centres.shape == (len(want), 3) and mol.centres.dtype == np.float64
    assert mol.radii.shape == (len(want),) and mol.radii.dtype == np.float64
    assert np.array_equal(mol.centres, want[:, :3])
    assert np.array_equal(mol.radii, want[:, 3])


def test_records_are_the_files(data):
    mol = surftrace.read(data / "structures/1crn.pdb")
    atoms = [line for line in open(data / "structures/1crn.pdb") if line.startswith("ATOM")]
    assert len(mol) == len(atoms) == 327
    assert mol.names == [a[12:16].strip() for a in atoms]
    assert mol.resnames == [a[17:20].strip() for a in atoms]
    assert mol.chains == [a[21].strip() for a in atoms]
    assert list(mol.resids) == [int(a[22:26]) for a in atoms]
    assert list(mol.serials) == [int(a[6:11]) for a in atoms]
    assert mol.elements == [a[76:78].strip() for a in atoms]
    assert list(mol.indices) == list(range(327))
    assert mol.source.endswith("1crn.pdb") and "327 atoms" in repr(mol)


def test_centres_and_radii_are_views_that_keep_the_molecule(data):
    mol = surftrace.read(data / "structures/1crn.pdb")
    first = mol.centres
    assert np.shares_memory(first, mol.centres), "each access should view the same memory, not copy"
    assert np.shares_memory(mol.radii, mol.radii)
    with pytest.raises(ValueError):
        first[0, 0] = 1.0  # read-only: the molecule is shared with its surfaces
    want = first.copy()
    del mol
    gc.collect()
    np.zeros((200000, 3))  # reuse freed memory, if any were freed
    assert np.array_equal(first, want)


def test_read_errors_are_python_exceptions(data, tool, tmp_path):
    for bad in sorted((data / "bad").iterdir()):
        cli = subprocess.run([tool, "info", str(bad)], capture_output=True, text=True)
        if cli.returncode == 0:
            surftrace.read(bad)
            continue
        with pytest.raises(ValueError) as e:
            surftrace.read(bad)
        assert bad.name in str(e.value), str(e.value)
    with pytest.raises(surftrace.InputError, match="truncated.pdb"):
        surftrace.read(data / "bad/truncated.pdb")
    with pytest.raises(ValueError, match="nope.pdb"):
        surftrace.read(tmp_path / "nope.pdb")


@pytest.mark.parametrize("kwargs, error", [
    ({"model": 0}, ValueError),
    ({"format": "mol2"}, ValueError),
    ({"default_radius": 0.0}, ValueError),
    ({"bead_radius": -1.0}, ValueError),
    ({"model": "two"}, TypeError),
])
def test_bad_read_choices(data, kwargs, error):
    with pytest.raises(error):
        surftrace.read(data / "structures/1crn.pdb", **kwargs)


def test_molecule_from_arrays():
    centres = np.array([[0, 0, 0], [1.5, 0, 0], [0, 1.5, 0]], dtype=np.float32) + np.float32(0.1)
    mol = surftrace.Molecule(centres, [1.7, 1.6, 1.5], elements=["C", "N", "O"], names=["CA", "N", "O"],
                             resids=np.array([1, 1, 2]), chains=["A", "A", "B"])
    assert len(mol) == 3
    assert np.array_equal(mol.centres, centres.astype(np.float64))  # widened exactly
    assert mol.elements == ["C", "N", "O"] and mol.names == ["CA", "N", "O"] and mol.chains == ["A", "A", "B"]
    assert list(mol.resids) == [1, 1, 2]
    assert len(mol.select("chain B")) == 1 and mol.select("element N").names == ["N"]
    strided = np.zeros((6, 4))
    strided[::2, :3] = centres
    assert not strided[::2, :3].flags.c_contiguous
    assert np.array_equal(surftrace.Molecule(strided[::2, :3], np.array([1.7, 1.6, 1.5])).centres, mol.centres)
    assert np.array_equal(surftrace.Molecule(np.arange(9).reshape(3, 3), [1, 2, 3]).radii, [1.0, 2.0, 3.0])


nan_centres = np.zeros((3, 3))
nan_centres[1, 2] = np.nan


@pytest.mark.parametrize("centres, radii, error, words", [
    (np.zeros((3, 2)), np.ones(3), ValueError, "centres: expected shape (n, 3), got (3, 2)"),
    (np.zeros(9), np.ones(3), ValueError, "centres: expected shape (n, 3)"),
    (np.zeros((3, 3, 1)), np.ones(3), ValueError, "centres"),
    (np.zeros((3, 3)), np.ones(2), ValueError, "radii: expected 3 values"),
    (np.zeros((3, 3)), np.ones((3, 1)), ValueError, "radii: expected shape (n,)"),
    (nan_centres, np.ones(3), ValueError, "centres[1, 2] is nan"),
    (np.full((3, 3), np.inf), np.ones(3), ValueError, "centres[0, 0] is inf"),
    (np.eye(3), np.array([1.0, 0.0, 1.0]), ValueError, "radii[1] is 0.0"),
    (np.eye(3), np.array([1.0, -1.0, 1.0]), ValueError, "radii[1]"),
    (np.eye(3), np.array([1.0, np.nan, 1.0]), ValueError, "radii[1] is nan"),
    (np.zeros((0, 3)), np.ones(0), ValueError, "no atoms"),
    (np.eye(3) * 1e9, np.ones(3), ValueError, "beyond"),
    (np.eye(3).astype(np.complex128), np.ones(3), TypeError, "centres: expected numbers"),
    (np.array([["a", "b", "c"]] * 3), np.ones(3), TypeError, "centres"),
    (np.eye(3).astype(object), np.ones(3), TypeError, "centres"),
    (None, np.ones(3), TypeError, "centres"),
    ("not an array", np.ones(3), TypeError, "centres"),
    (np.eye(3), "1 2 3", TypeError, "radii"),
])
def test_bad_arrays_raise(centres, radii, error, words):
    with pytest.raises(error) as e:
        surftrace.Molecule(centres, radii)
    assert words in str(e.value)


@pytest.mark.parametrize("field, value, error", [
    ("elements", ["C", "N"], ValueError),
    ("names", "CA", TypeError),
    ("names", ["CA", 3, "O"], TypeError),
    ("resids", [1.5, 2, 3], TypeError),
    ("chains", None, None),
])
def test_bad_records_raise(field, value, error):
    if error is None:
        assert len(surftrace.Molecule(np.eye(3), np.ones(3), **{field: value})) == 3
        return
    with pytest.raises(error, match=field):
        surftrace.Molecule(np.eye(3), np.ones(3), **{field: value})


def _mda_select():
    spec = importlib.util.spec_from_file_location(
        "mda_select", __import__("pathlib").Path(__file__).parents[1] / "oracles" / "mda_select.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# The topologies with coordinates and selections of tests/build/atom_selection_test.cpp.
SELECTIONS = {
    "formats/gro/ubiquitin.gro": ["water", "not water", "water and name O*", "protein or water",
                                  "water or resid 1 and not backbone", "resid 1-5 and backbone", "index 1404",
                                  "name CA and resid 70-76", "name C*", "name [CN]A", "resid 10-20 30:35 40 to 42",
                                  "not (resid 1-60 or name CA)", "(resname LYS ARG) and (name NZ or name NH*)"],
    "structures/1ubq.pdb.gz": ["chain A and resid 1-10", "element S", "element C N and not name CA",
                               "element [NO] and resid 1", "protein and element O", "resname HOH and index 600-610",
                               "water", "backbone", "name CA, resid 3"],
    "small/elements.pdb": ["element Fe Cu", "element C* and not element Ca", "element ?", "element H",
                           "resname Mg Ca", "not element C H N O S"],
    "small/tiny.pdb": ["chain C E", "chain E and not water", "resname UNK or resname HOH"],
    "trajectories/cobrotoxin/cobrotoxin.pdb.gz": ["water", "not water and not protein", "protein and name CA",
                                                  "index 19000-19384", "atom 19385", "resname NA CL"],
}


@pytest.mark.parametrize("name", sorted(SELECTIONS))
def test_select_equals_mdanalysis(data, name):
    MDAnalysis = pytest.importorskip("MDAnalysis")
    from MDAnalysis.core import selection as mda_selection
    oracle = _mda_select()
    warnings.simplefilter("ignore")
    u = MDAnalysis.Universe(str(data / name))
    has_chain_ids = hasattr(u.atoms, "chainIDs")
    has_water = "water" in mda_selection._SELECTIONDICT
    mol = surftrace.read(data / name, water=True)
    present = set(mol.indices.tolist())
    for s in SELECTIONS[name]:
        theirs = [i for i in sorted(u.select_atoms(oracle.translate(s, has_chain_ids, has_water)).indices)
                  if i in present]
        assert theirs, f"{s!r} selects nothing in MDAnalysis: choose another"
        picked = mol.select(s)
        assert picked.indices.tolist() == theirs, s
        rows = [mol.indices.tolist().index(i) for i in theirs]
        assert np.array_equal(picked.centres, mol.centres[rows]) and np.array_equal(picked.radii, mol.radii[rows])


def test_select_errors_are_value_errors_with_a_caret(data):
    mol = surftrace.read(data / "structures/1crn.pdb")
    with pytest.raises(ValueError) as e:
        mol.select("name CA and and resid 3")
    assert "^" in str(e.value) and "name CA and and resid 3" in str(e.value)
    with pytest.raises(ValueError, match="HOH"):
        mol.select("resname HOH")  # selects nothing
    with pytest.raises(TypeError):
        mol.select(3)


def _tiled_1aon(data, tmp_path):
    """1AON's atom records three times over: as read, moved 500 Å along x, and as read again
    (every atom of the third copy exactly on one of the first: a duplicate)."""
    import gzip
    with gzip.open(data / "paper/1aon.pdb.gz", "rt") as f:
        atoms = [line.rstrip("\n") for line in f if line.startswith(("ATOM", "HETATM"))]
    moved = [a[:30] + "%8.3f" % (float(a[30:38]) + 500.0) + a[38:] for a in atoms]
    copies = [atoms, moved, atoms]
    pdb = tmp_path / "tiled.pdb"
    pdb.write_text("".join("\n".join(c) + "\nTER\n" for c in copies) + "END\n")
    gro = tmp_path / "tiled.gro"
    lines = ["1AON three times", "%5d" % (3 * len(atoms))]
    for c in copies:
        for a in c:
            x, y, z = (float(a[30 + 8 * k:38 + 8 * k]) / 10 for k in range(3))
            lines.append("%5d%-5s%5s%5d%8.3f%8.3f%8.3f" % (int(a[22:26]) % 100000, a[17:20].strip(), a[12:16].strip(),
                                                      int(a[6:11]) % 100000, x, y, z))
    lines.append("%10.5f%10.5f%10.5f" % (100.0, 100.0, 100.0))
    gro.write_text("\n".join(lines) + "\n")
    return pdb, gro, len(atoms)


def test_large_files_equal_mdanalysis(data, tmp_path):
    """Files of 177k atoms (several MB, read in pieces, their duplicates searched in partitions)
    read as MDAnalysis reads them: the same atoms in file order, names, residues and coordinates;
    the third copy left out as duplicates, and the XYZR of them as numpy's loadtxt reads it."""
    MDAnalysis = pytest.importorskip("MDAnalysis")
    warnings.simplefilter("ignore")
    pdb, gro, n = _tiled_1aon(data, tmp_path)
    for path in (pdb, gro):
        mol = surftrace.read(path, water=True)
        u = MDAnalysis.Universe(str(path))
        assert len(u.atoms) == 3 * n
        assert mol.indices.tolist() == list(range(2 * n)), path
        assert any("%d atoms lie exactly on an earlier atom" % n in note for note in mol.notes), mol.notes
        theirs = u.atoms[:2 * n]
        assert mol.names == list(theirs.names)
        assert mol.resnames == list(theirs.resnames)
        assert mol.resids.tolist() == [int(r) for r in theirs.resids]
        # MDAnalysis holds float32 coordinates.
        np.testing.assert_allclose(mol.centres, theirs.positions.astype(np.float64), rtol=0, atol=2e-5 * 500)
        if path == pdb:
            assert mol.chains == list(theirs.chainIDs)
            assert mol.serials.tolist() == [int(s) for s in theirs.ids]
    xyzr = tmp_path / "tiled.xyzr"
    want = surftrace.read(pdb)
    rows = ["%.3f %.3f %.3f %.2f" % (c[0], c[1], c[2], r) for c, r in zip(want.centres, want.radii)]
    xyzr.write_text("\n".join(rows + rows[:n]) + "\n")
    mol = surftrace.read(xyzr)
    oracle = np.loadtxt(xyzr)
    assert len(mol) == 2 * n
    assert np.array_equal(mol.centres, oracle[:2 * n, :3]) and np.array_equal(mol.radii, oracle[:2 * n, 3])
