"""surftrace.ses, skin, sas, vdw, load and Surface: the areas, volumes and files of the
`surftrace` program, bit for bit."""
import math

import numpy as np
import pytest

import surftrace

STRUCTURES = ["structures/1crn.pdb", "structures/1ubq.pdb.gz"]


@pytest.mark.parametrize("name", STRUCTURES)
def test_ses_areas_equal_the_area_command(data, run_tool, name):
    want = run_tool("area", data / name, "--format", "json", parse_json=True)
    s = surftrace.ses(surftrace.read(data / name), probe=1.4)
    assert s.kind == "ses" and s.probe == 1.4
    assert s.area == want["ses"]["total"]
    assert s.volume == want["ses"]["volume"]
    assert s.area_by_kind == {k: want["ses"][k] for k in ("convex", "toroidal", "concave")}
    assert s.atom_area.dtype == np.float64 and s.atom_area.shape == (want["atoms"],)
    assert s.atom_area.tolist() == want["ses"]["per_atom"]
    assert s.sas_area == want["sas"]["total"]
    assert s.sas_atom_area.tolist() == want["sas"]["per_atom"]
    assert s.components == want["ses"]["components"]
    assert s.component_areas.tolist() == [c["area"] for c in want["ses"]["components"]]
    assert s.component_volumes.tolist() == [c["volume"] for c in want["ses"]["components"]]
    assert s.cavities.tolist() == [c["cavity"] for c in want["ses"]["components"]]
    assert np.shares_memory(s.atom_area, s.atom_area), "per-atom areas should be a view, not a copy"


def test_other_probe_and_dropped_cavities(data, run_tool):
    path = data / "structures/1crn.pdb"
    want = run_tool("area", path, "--probe", "1.1", "--drop-cavities", "--format", "json", parse_json=True)
    s = surftrace.ses(surftrace.read(path), probe=1.1, drop_cavities=True)
    assert s.area == want["ses"]["total"] and s.volume == want["ses"]["volume"]
    assert s.components == want["ses"]["components"]
    assert not any(c["cavity"] for c in s.components)


@pytest.mark.parametrize("name", STRUCTURES)
def test_skin_areas_equal_the_area_command(data, run_tool, name):
    want = run_tool("area", data / name, "--surface", "mss", "--shrink", "0.4", "--format", "json", parse_json=True)
    s = surftrace.skin(surftrace.read(data / name), shrink=0.4)
    assert s.kind == "mss" and s.shrink == 0.4
    assert s.area == want["mss"]["total"] and s.volume == want["mss"]["volume"]
    assert s.atom_area.tolist() == want["mss"]["per_atom"]
    assert s.area_error_estimate == want["mss"]["area_error_estimate"]
    assert s.components == []


def test_save_writes_the_bytes_of_build_and_load_reads_them(data, run_tool, tmp_path):
    path = data / "structures/1crn.pdb"
    run_tool("build", path, "-o", tmp_path / "cli.stp")
    s = surftrace.ses(surftrace.read(path))
    s.save(tmp_path / "py.stp")
    assert (tmp_path / "py.stp").read_bytes() == (tmp_path / "cli.stp").read_bytes()
    loaded = surftrace.load(str(tmp_path / "py.stp"))
    assert loaded.molecule is None and loaded.kind == "ses"
    assert loaded.area == s.area and loaded.volume == s.volume
    assert loaded.atom_area.tolist() == s.atom_area.tolist()
    assert loaded.patch_counts == s.patch_counts
    info = run_tool("info", tmp_path / "py.stp", "--json", parse_json=True)
    assert s.patch_counts == {k: info["patches"][k] for k in ("convex", "toroidal", "concave")}
    assert len(s.components) == info["components"]
    with pytest.raises(ValueError, match="nope.stp"):
        surftrace.load(tmp_path / "nope.stp")


def test_vdw_and_sas(data, run_tool):
    mol = surftrace.read(data / "structures/1crn.pdb")
    ses = surftrace.ses(mol)
    sas = surftrace.sas(mol, probe=1.4)
    assert sas.kind == "sas" and sas.area == ses.sas_area
    assert sas.atom_area.tolist() == ses.sas_atom_area.tolist()
    with pytest.raises(ValueError, match="SAS"):
        sas.volume
    vdw = surftrace.vdw(mol)
    assert vdw.kind == "vdw" and 0 < vdw.patch_counts["convex"] <= len(mol)
    # The union of the balls: the skin at s = 1 (`area --surface mss --shrink 1`).
    want = run_tool("area", data / "structures/1crn.pdb", "--surface", "mss", "--shrink", "1", "--format", "json",
                    parse_json=True)
    assert vdw.area == want["mss"]["total"] and vdw.volume == want["mss"]["volume"]
    assert 0 < vdw.area < sum(4 * math.pi * r * r for r in mol.radii)


def test_bad_surface_arguments(data):
    mol = surftrace.read(data / "structures/1crn.pdb")
    for call, error in [(lambda: surftrace.ses(mol, probe=0), ValueError),
                        (lambda: surftrace.ses(mol, probe=float("nan")), ValueError),
                        (lambda: surftrace.skin(mol, shrink=1.5), ValueError),
                        (lambda: surftrace.skin(mol, shrink=0), ValueError),
                        (lambda: surftrace.ses("1crn.pdb"), TypeError),
                        (lambda: surftrace.ses(mol, merge_within=-1), ValueError)]:
        with pytest.raises(error):
            call()


def test_surface_keeps_its_molecule(data):
    s = surftrace.ses(surftrace.read(data / "structures/1crn.pdb").select("resid 1-10"))
    assert len(s.molecule) == len(s.atom_area) and s.molecule.resids.max() == 10
    assert s.area == pytest.approx(s.atom_area.sum(), rel=1e-12)
