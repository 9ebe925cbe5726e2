"""surftrace.compare: an Image, a file, or another renderer's buffers held in numpy against a
reference; the report is the CLI's (`surftrace compare --report`), the errors ValueError."""
import json
import shutil
import subprocess

import numpy as np
import pytest

import surftrace
from image_helpers import TOOL, cli, cli_render, ses

SIZE = 96


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("compare")


@pytest.fixture(scope="module")
def reference(folder):
    return surftrace.render(ses(), size=(SIZE, SIZE))


@pytest.fixture(scope="module")
def reference_exr(reference, folder):
    reference.save(folder / "reference.exr")
    return folder / "reference.exr"


def window_depth(image):
    """GL window depth of the image's hits (glDepthRange 0..1), rows bottom first as glReadPixels
    gives them, from its view depth and the projection matrix: background 1."""
    p = image.camera.projection_matrix
    hit = np.isfinite(image.depth_z)
    z_view = -np.where(hit, image.depth_z, 1.0).astype(np.float64)
    ndc = (p[2, 2] * z_view + p[2, 3]) / (p[3, 2] * z_view)
    window = np.where(hit, (ndc + 1) / 2, 1.0)
    return np.flipud(window).astype(np.float32)


def view_normals(image):
    """World normals into the view frame (x right, y up, z towards the eye), rows bottom first."""
    rotation = image.camera.view_matrix[:3, :3]
    return np.flipud(image.normal @ rotation.T).astype(np.float32)


def write_pfm(path, values):
    """A greyscale PFM: rows bottom first (the array's first row goes first), little-endian."""
    h, w = values.shape
    path.write_bytes(b"Pf\n%d %d\n-1.0\n" % (w, h) + np.ascontiguousarray(values, dtype="<f4").tobytes())


COMPARE_KEYS = {"passed", "verdict", "preset", "preset_choice", "violations", "hints", "notes", "not_compared",
                "settings", "summary", "test", "reference"}


def figures(report):
    return {k: v for k, v in report.items() if k not in COMPARE_KEYS}


def test_an_image_against_itself_passes(reference):
    report = surftrace.compare(reference, reference)
    assert report["passed"] is True and report["violations"] == []
    assert report["preset"] == "exact"
    assert report["verdict"].startswith("PASS")
    assert report["depth"]["max"] == 0.0 and report["coverage"]["mismatch"] == 0
    assert report["pixels"] == SIZE * SIZE


def test_files_and_images_mix(reference, reference_exr):
    for test, ref in ((reference_exr, reference), (reference, reference_exr), (str(reference_exr), str(reference_exr))):
        assert surftrace.compare(test, ref)["passed"]


def test_window_depth_held_in_numpy_passes(reference):
    report = surftrace.compare({"depth": window_depth(reference), "normal": view_normals(reference)}, reference)
    assert report["passed"], report["verdict"]
    assert report["preset"] == "foreign"
    assert report["depth"]["p99"] < 1e-3 and report["normal_degrees"]["p99"] < 0.01


def test_ray_depth_top_down_passes(reference):
    report = surftrace.compare({"depth": reference.depth_t}, reference, depth_convention="ray", origin="top-left")
    assert report["passed"], report["verdict"]
    assert report["depth"]["max"] < 1e-4
    assert any("normal" in line for line in report["not_compared"]) or report["normal_degrees"]["samples"] == 0


def test_non_contiguous_and_float64_arrays_work(reference):
    depth = np.asfortranarray(np.flipud(reference.depth_z).astype(np.float64))
    assert not depth.flags.c_contiguous
    report = surftrace.compare({"depth": depth[:, :, None]}, reference, depth_convention="view-z")
    assert report["passed"], report["verdict"]


def test_depth_shifted_by_a_fifth_of_an_angstrom_fails(reference):
    """View depth 0.2 Å too far is 0.2·t/z Å along each pixel's ray (the pinhole factor, 1 at the
    centre): the report's p99 is that factor's 99th percentile times 0.2, within the masks' reach."""
    depth = np.flipud(reference.depth_z) + np.float32(0.2)
    report = surftrace.compare({"depth": depth}, reference, depth_convention="view-z")
    assert report["passed"] is False
    assert "\nFAIL (foreign" in report["verdict"]
    assert any("depth" in v for v in report["violations"])
    hit = np.isfinite(reference.depth_t)
    factor = (reference.depth_t[hit] / reference.depth_z[hit]).astype(np.float64)
    assert 0.2 * factor.min() - 1e-4 <= report["depth"]["p99"] <= 0.2 * factor.max() + 1e-4
    assert report["depth"]["p99"] == pytest.approx(0.2 * np.percentile(factor, 99), abs=2e-3)
    assert report["depth"]["median"] == pytest.approx(0.2 * np.median(factor), abs=2e-3)


def test_report_equals_the_cli_report(reference, reference_exr, folder):
    """The same buffers as a PFM file through `surftrace compare --report` and as an array."""
    depth = np.flipud(reference.depth_z) + np.float32(0.05)
    write_pfm(folder / "test.pfm", depth)
    done = subprocess.run([TOOL, "compare", folder / "test.pfm", reference_exr, "--depth-convention", "view-z",
                           "--report", folder / "report.json"], capture_output=True, text=True)
    assert done.returncode in (0, 2), done.stderr
    report = surftrace.compare({"depth": depth}, reference_exr, depth_convention="view-z")
    cli_report = json.loads((folder / "report.json").read_text())
    assert figures(report) == cli_report
    assert report["passed"] == (done.returncode == 0)
    assert report["verdict"] in done.stdout


def test_report_of_two_exrs_equals_the_cli(folder):
    embree, _, _ = cli_render(folder, "e", "--size", "48x48")
    shutil.copy(embree, folder / "e2.exr")
    cli("compare", folder / "e2.exr", embree, "--report", folder / "same.json")
    report = surftrace.compare(folder / "e2.exr", embree)
    assert figures(report) == json.loads((folder / "same.json").read_text())
    assert report["passed"]


def test_nan_is_a_mismatch_not_background(reference):
    depth = window_depth(reference)
    depth[SIZE // 2, SIZE // 2] = np.nan
    report = surftrace.compare({"depth": depth}, reference)
    assert report["passed"] is False
    assert report["nan"]["test"]["pixels"] == 1 and report["nan"]["reference"]["pixels"] == 0


@pytest.mark.parametrize("test, options, match", [
    ({"depth": np.zeros((SIZE, SIZE), np.int32)}, {}, "dtype"),
    ({"depth": np.zeros((SIZE, SIZE, 2), np.float32)}, {}, "shape"),
    ({"depth": np.zeros((SIZE,), np.float32)}, {}, "shape"),
    ({"depth": np.zeros((SIZE, SIZE // 2), np.float32)}, {}, ""),
    ({"depth": np.ones((SIZE, SIZE), np.float32), "normal": np.zeros((SIZE, SIZE), np.float32)}, {}, "normal"),
    ({"depth": np.ones((SIZE, SIZE), np.float32), "normal": np.zeros((8, 8, 3), np.float32)}, {}, "normal"),
    ({"depth": "nope"}, {}, "dtype"),
    ({"normal": np.zeros((SIZE, SIZE, 3), np.float32)}, {}, "depth"),
    ({"depth": np.ones((SIZE, SIZE), np.float32), "colour": 1}, {}, "colour"),
    ({"depth": np.full((SIZE, SIZE), 2.0, np.float32)}, {}, "window"),
    ({"depth": np.ones((SIZE, SIZE), np.float32)}, {"depth_convention": "linear"}, "linear"),
    ({"depth": np.ones((SIZE, SIZE), np.float32)}, {"origin": "middle"}, "middle"),
    ({"depth": np.ones((SIZE, SIZE), np.float32)}, {"preset": "lenient"}, "preset"),
    ({"depth": np.ones((SIZE, SIZE), np.float32)}, {"max_coverage": 2}, "max_coverage"),
    (42, {}, "test"),
])
def test_bad_buffers_raise_value_error(reference, test, options, match):
    with pytest.raises(ValueError, match=match):
        surftrace.compare(test, reference, **options)


def test_other_errors(reference, folder):
    with pytest.raises(ValueError, match="another renderer"):
        surftrace.compare(reference, reference, depth_convention="ray")
    with pytest.raises(TypeError, match="max_depth"):
        surftrace.compare(reference, reference, max_depth=1)
    with pytest.raises(FileNotFoundError):
        surftrace.compare(folder / "missing.exr", reference)
    with pytest.raises(ValueError, match="reference"):
        surftrace.compare(reference, {"depth": np.ones((SIZE, SIZE), np.float32)})


def test_reference_without_camera_raises(reference_exr, folder):
    if shutil.which("oiiotool") is None:
        pytest.skip("oiiotool not installed")
    plain = folder / "nocamera.exr"
    subprocess.run(["oiiotool", reference_exr, "--eraseattrib", "surftrace:camera", "-o", plain], check=True)
    with pytest.raises(ValueError, match="camera"):
        surftrace.compare({"depth": np.ones((SIZE, SIZE), np.float32)}, plain)
