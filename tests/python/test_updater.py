"""surftrace.Updater: the same surface frame after frame, equal bit for bit to full builds,
from an MDAnalysis loop; and its checks on the positions it is given."""
import warnings

import numpy as np
import pytest

import surftrace


def same_surface(a, b, tmp_path):
    assert a.area == b.area and a.volume == b.volume
    assert a.atom_area.tolist() == b.atom_area.tolist()
    a.save(tmp_path / "a.stp")
    b.save(tmp_path / "b.stp")
    assert (tmp_path / "a.stp").read_bytes() == (tmp_path / "b.stp").read_bytes()


def test_mdanalysis_loop_equals_full_builds_and_the_command_line(data, run_tool, tmp_path):
    MDAnalysis = pytest.importorskip("MDAnalysis")
    warnings.simplefilter("ignore")
    psf, dcd = data / "trajectories/adk_dims/adk.psf.gz", data / "trajectories/adk_dims/adk_dims.dcd"
    frames = [0, 1, 2, 40]
    mol = surftrace.read(psf, trajectory=dcd)
    u = MDAnalysis.Universe(str(psf), str(dcd))
    atoms = u.atoms[mol.indices]
    upd = surftrace.Updater(mol, surface="ses", probe=1.4)
    cli = run_tool("area", psf, dcd, "--frames", "0:3", "--format", "json", parse_json=True)["frames"]
    for ts in u.trajectory[frames]:
        assert atoms.positions.dtype == np.float32
        s = upd.update(atoms.positions)
        full = surftrace.ses(surftrace.read(psf, trajectory=dcd, frame=ts.frame))
        same_surface(s, full, tmp_path)
        if ts.frame < 3:
            assert s.area == cli[ts.frame]["ses"] and s.volume == cli[ts.frame]["ses_volume"]
    assert 0 < upd.recomputed <= len(mol)


@pytest.mark.parametrize("surface, build", [("ses", lambda m: surftrace.ses(m)),
                                            ("skin", lambda m: surftrace.skin(m, shrink=0.5))])
def test_moving_a_few_atoms_recomputes_few(data, tmp_path, surface, build):
    mol = surftrace.read(data / "structures/1crn.pdb")
    upd = surftrace.Updater(mol, surface=surface)
    first = upd.update(mol.centres)
    assert upd.recomputed == len(mol)
    same_surface(first, build(mol), tmp_path)
    moved = [5, 6, 100]
    positions = mol.centres.copy()
    positions[moved] += [0.3, -0.2, 0.1]
    for given in (moved, None):
        s = upd.update(positions if given is None else positions.copy(), moved=given)
        assert 0 < upd.recomputed < len(mol)
        # A full build of the same atoms (records, radii set, checksum) at these positions: a
        # fresh updater's first frame; and the areas of a molecule made of these arrays alone.
        fresh = surftrace.Updater(mol, surface=surface)
        same_surface(s, fresh.update(positions), tmp_path)
        assert fresh.recomputed == len(mol)
        alone = build(surftrace.Molecule(positions, mol.radii))
        assert s.area == alone.area and s.atom_area.tolist() == alone.atom_area.tolist()
        positions[moved] -= [0.3, -0.2, 0.1]


def test_bad_positions_raise(data):
    mol = surftrace.read(data / "structures/1crn.pdb")
    upd = surftrace.Updater(mol)
    upd.update(mol.centres)
    bad = mol.centres.copy()
    bad[3, 1] = np.nan
    for positions, moved, error, words in [
        (mol.centres[:, :2], None, ValueError, "positions: expected shape (n, 3)"),
        (mol.centres[:-1], None, ValueError, "expected 327 rows"),
        (bad, None, ValueError, "positions[3, 1] is nan"),
        (mol.centres.astype(np.complex64), None, TypeError, "positions"),
        (mol.centres, [400], ValueError, "moved[0]"),
        (mol.centres + 1.0, [0, 1], ValueError, "atom 2 moved but is not listed"),
    ]:
        with pytest.raises(error) as e:
            upd.update(positions, moved=moved)
        assert words in str(e.value)
    with pytest.raises(ValueError):
        surftrace.Updater(mol, surface="cartoon")
    with pytest.raises(ValueError):
        surftrace.Updater(mol, surface="skin", shrink=2.0)
    # Strided and float32 positions are taken as they are.
    strided = np.zeros((len(mol), 6))
    strided[:, ::2] = mol.centres
    assert upd.update(strided[:, ::2]).area == surftrace.ses(mol).area


def test_whole_file_positions_name_the_fix(data):
    mol = surftrace.read(data / "structures/1ubq.pdb.gz")  # waters left out
    assert len(mol) < mol.file_atom_count
    with pytest.raises(ValueError, match="molecule.indices"):
        surftrace.Updater(mol).update(np.zeros((mol.file_atom_count, 3)))
