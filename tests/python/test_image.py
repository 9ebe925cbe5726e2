"""surftrace.Camera, surftrace.render and surftrace.Image: the same pixels, buffers and camera as
`surftrace render`, matrices equal to OpenGL's formulas written out in numpy, buffers without copies."""
import json
import math

import numpy as np
import pytest
from PIL import Image as PILImage

import surftrace
from image_helpers import BUFFERS, CRAMBIN, buffers_equal, cli_render, ses

SIZE = 128


@pytest.fixture(scope="module")
def surface():
    return ses()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("image")


@pytest.fixture(scope="module")
def embree(surface, folder):
    """The CLI's render of 1CRN at 128² and the same from Python."""
    exr, png, camera = cli_render(folder, "cli", "--size", f"{SIZE}x{SIZE}")
    return {"exr": exr, "png": png, "camera": camera, "image": surftrace.render(surface, size=(SIZE, SIZE))}


# ---- Images equal the CLI's -------------------------------------------------------------------


def test_every_buffer_equals_the_cli_exr(embree):
    cli = surftrace.Image.load(embree["exr"])
    image = embree["image"]
    assert (image.width, image.height) == (SIZE, SIZE)
    assert image.seam_distance is not None, "masks are recorded by default, as `render --exr` records them"
    assert buffers_equal(image, cli) == []
    assert image.engine == "embree"


def test_png_equals_the_cli_png(embree, folder):
    """Read back by PIL, not by SurfTrace: _repr_png_, save() and the CLI's -o agree pixel for pixel."""
    cli = np.asarray(PILImage.open(embree["png"]))
    (folder / "repr.png").write_bytes(embree["image"]._repr_png_())
    embree["image"].save(folder / "saved.png")
    for path in ("repr.png", "saved.png"):
        ours = np.asarray(PILImage.open(folder / path))
        assert ours.shape == cli.shape == (SIZE, SIZE, 3)
        assert np.array_equal(ours, cli), path


def srgb_codes(linear):
    """The sRGB transfer function (IEC 61966-2-1) written out: linear [0, 1] to 8-bit codes."""
    v = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.rint(255.0 * np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055))


def test_rgb_is_linear_and_the_png_its_srgb_encoding(embree):
    """rgb holds the linear colour; the PNG (row 0 its top row) holds its sRGB codes and says so."""
    image = PILImage.open(embree["png"])
    assert "srgb" in image.info, "the PNG has no sRGB chunk"
    png = np.asarray(image).astype(np.float64)
    assert np.abs(srgb_codes(embree["image"].rgb) - png).max() <= 1
    mid = (embree["image"].rgb > 0.1) & (embree["image"].rgb < 0.6)
    assert (png[mid] - np.rint(255 * embree["image"].rgb[mid]) >= 40).sum() > 100, "not told apart from linear codes"


def test_saved_exr_holds_every_buffer(embree, folder):
    embree["image"].save(folder / "saved.exr")
    assert buffers_equal(surftrace.Image.load(folder / "saved.exr"), embree["image"]) == []


def test_render_from_the_cli_camera_equals_the_cli(embree, surface):
    camera = surftrace.Camera.load(embree["camera"])
    image = surftrace.render(surface, camera=camera)
    assert buffers_equal(image, surftrace.Image.load(embree["exr"])) == []


def test_gl_equals_the_cli_gl(surface, folder):
    try:
        image = surftrace.render(surface, size=(SIZE, SIZE), engine="gl")
    except RuntimeError as e:  # no OpenGL 4.5 context on this machine
        pytest.skip(f"GL engine unavailable: {e}")
    exr, _, _ = cli_render(folder, "gl", "--size", f"{SIZE}x{SIZE}", "--engine", "gl")
    assert image.engine == "gl"
    assert image.seam_distance is None
    assert buffers_equal(image, surftrace.Image.load(exr)) == []


def test_options_equal_the_cli_options(surface, folder):
    options = dict(color="element", background=(0.1, 0.2, 0.3), spp=4, shadows=True, silhouettes=True,
                   crease_angle=40.0, depth_cue=True, depth_darkening=True, depth_darkening_sigma=0.05,
                   view=(1, -0.5, 0.25))
    image = surftrace.render(surface, size=(64, 48), **options)
    exr, _, _ = cli_render(folder, "options", "--size", "64x48", "--color", "element", "--background", "0.1,0.2,0.3",
                           "--spp", "4", "--shadows", "--silhouettes", "--crease-angle", "40", "--depth-cue",
                           "--depth-darkening", "--depth-darkening-sigma", "0.05", "--view", "1,-0.5,0.25")
    assert buffers_equal(image, surftrace.Image.load(exr)) == []


@pytest.mark.parametrize("preset", ["simple", "soft", "full"])
def test_lighting_equals_the_cli_lighting(surface, folder, preset):
    """lighting= is the CLI's --lighting: the same buffers, and a picture other than the headlight's."""
    image = surftrace.render(surface, size=(40, 32), lighting=preset)
    exr, _, _ = cli_render(folder, f"lighting-{preset}", "--size", "40x32", "--lighting", preset)
    assert buffers_equal(image, surftrace.Image.load(exr)) == []
    headlight = surftrace.render(surface, size=(40, 32))
    covered = np.isfinite(image.depth_t)
    assert covered.sum() > 200
    assert np.abs(image.rgb[covered] - headlight.rgb[covered]).max() > 0.05


# ---- Buffers: shapes, row order, no copies ---------------------------------------------------


def test_buffers_share_the_image_memory(embree):
    image = embree["image"]
    shapes = {"rgb": (SIZE, SIZE, 3), "normal": (SIZE, SIZE, 3), "alpha": (SIZE, SIZE)}
    for name in BUFFERS:
        a = getattr(image, name)
        assert a.shape == shapes.get(name, (SIZE, SIZE)), name
        assert a.dtype == (np.uint32 if name in ("patch_kind", "patch_id", "atom_id", "flags") else np.float32), name
        assert not a.flags.writeable, name
        assert not a.flags.owndata, name
    # rgb and alpha are views of one RGBA buffer; two reads of a buffer are one memory.
    assert np.shares_memory(image.rgb, image.rgba) and np.shares_memory(image.alpha, image.rgba)
    assert image.rgb.ctypes.data == image.rgba.ctypes.data
    assert image.alpha.ctypes.data == image.rgba.ctypes.data + 12
    assert image.depth_t.ctypes.data == image.depth_t.ctypes.data
    with pytest.raises(ValueError):
        image.depth_t[0, 0] = 1.0


def test_buffers_outlive_the_image(surface):
    image = surftrace.render(surface, size=(32, 32))
    depth, expected = image.depth_t, image.depth_t.copy()
    del image
    import gc

    gc.collect()
    assert np.array_equal(depth, expected)


def crambin_centres():
    """1CRN's atom centres read straight from the PDB's ATOM records (columns 31-54)."""
    lines = [l for l in CRAMBIN.read_text().splitlines() if l.startswith("ATOM")]
    return np.array([[float(l[30:38]), float(l[38:46]), float(l[46:54])] for l in lines])


def pixel_rays(camera):
    """Unit pinhole rays through the pixel centres, row 0 at the top (the camera's formula)."""
    eye, at, up = (np.array(v) for v in (camera.eye, camera.look_at, camera.up))
    f = (at - eye) / np.linalg.norm(at - eye)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    h = math.tan(math.radians(camera.fov) / 2)
    aspect = camera.width / camera.height
    sx = (np.arange(camera.width) + 0.5) * 2 / camera.width - 1
    sy = (np.arange(camera.height) + 0.5) * 2 / camera.height - 1
    d = f + sx[None, :, None] * h * aspect * r - sy[:, None, None] * h * u
    return eye, d / np.linalg.norm(d, axis=2, keepdims=True), f


def test_rows_run_from_the_top(embree):
    """A convex pixel's hit point eye + t·dir lies on its atom's van der Waals sphere (C, N, O, S
    radii 1.52..1.80 Å): with rows upside down it would not."""
    image = embree["image"]
    eye, rays, forward = pixel_rays(image.camera)
    convex = image.patch_kind == 1
    assert convex.sum() > 1000
    points = eye + image.depth_t[..., None] * rays
    centres = crambin_centres()[image.atom_id[convex]]
    distance = np.linalg.norm(points[convex] - centres, axis=1)
    assert np.all((distance > 1.5) & (distance < 1.81)), (distance.min(), distance.max())
    # depth_z is the distance along the view direction.
    hit = np.isfinite(image.depth_t)
    assert np.allclose(image.depth_z[hit], (image.depth_t[hit][:, None] * rays[hit]) @ forward, rtol=1e-5)


# ---- Camera ----------------------------------------------------------------------------------


def test_camera_json_round_trip_equals_the_cli_file(embree, folder):
    text = embree["camera"].read_text()
    camera = embree["image"].camera
    camera.save(folder / "saved.json")
    assert (folder / "saved.json").read_text() == text
    assert json.loads(camera.to_json()) == json.loads(text)
    assert surftrace.Camera.from_json(text) == camera
    assert surftrace.Camera.from_json(embree["camera"]) == camera
    assert surftrace.Camera.from_json(str(embree["camera"])).to_json() == camera.to_json()


def test_camera_fields_match_the_json(embree):
    camera = embree["image"].camera
    j = json.loads(embree["camera"].read_text())
    assert (camera.width, camera.height, camera.projection) == (j["width"], j["height"], j["projection"])
    assert camera.eye == tuple(j["eye"]) and camera.look_at == tuple(j["look_at"]) and camera.up == tuple(j["up"])
    assert (camera.fov, camera.near, camera.far) == (j["fov_y_degrees"], j["near"], j["far"])
    # The JSON's matrices are column-major: the arrays are their transposes, rows as on paper.
    assert np.array_equal(camera.view_matrix, np.array(j["view_matrix"]).reshape(4, 4).T)
    assert np.array_equal(camera.projection_matrix, np.array(j["projection_matrix"]).reshape(4, 4).T)


def look_at(eye, centre, up):
    f = (centre - eye) / np.linalg.norm(centre - eye)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fov_degrees, aspect, near, far):
    f = 1 / math.tan(math.radians(fov_degrees) / 2)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])


def ortho(left, right, bottom, top, near, far):
    return np.array([[2 / (right - left), 0, 0, -(right + left) / (right - left)],
                     [0, 2 / (top - bottom), 0, -(top + bottom) / (top - bottom)],
                     [0, 0, -2 / (far - near), -(far + near) / (far - near)], [0, 0, 0, 1]])


def test_matrices_are_opengl_formulas():
    camera = surftrace.Camera(eye=(3, -2, 25), look_at=(1, 0.5, -1), up=(0.1, 1, 0), fov=40, width=320, height=200,
                              near=5, far=60)
    assert camera.view_matrix.shape == camera.projection_matrix.shape == (4, 4)
    assert camera.view_matrix.dtype == np.float64
    eye, centre, up = np.array([3, -2, 25.0]), np.array([1, 0.5, -1]), np.array([0.1, 1, 0])
    assert np.allclose(camera.view_matrix, look_at(eye, centre, up), rtol=0, atol=1e-12)
    assert np.allclose(camera.projection_matrix, perspective(40, 320 / 200, 5, 60), rtol=1e-12, atol=0)
    camera.projection, camera.ortho_height = "orthographic", 30.0
    h = 15.0
    assert np.allclose(camera.projection_matrix, ortho(-h * 1.6, h * 1.6, -h, h, 5, 60), rtol=1e-12, atol=1e-15)


def test_from_matrices_gives_back_the_matrices():
    view = look_at(np.array([0, 10, 40.0]), np.array([0, 0, 0.0]), np.array([0, 1, 0.0]))
    projection = perspective(35, 4 / 3, 10, 80)
    camera = surftrace.Camera.from_matrices(400, 300, view, projection)
    assert (camera.width, camera.height, camera.projection) == (400, 300, "perspective")
    assert np.allclose(camera.view_matrix, view, atol=1e-9)
    assert np.allclose(camera.projection_matrix, projection, rtol=1e-9)
    assert camera.fov == pytest.approx(35)
    assert (camera.near, camera.far) == (pytest.approx(10), pytest.approx(80))


def test_camera_fields_write_and_save(tmp_path):
    camera = surftrace.Camera()
    camera.eye, camera.look_at, camera.up = (1, 2, 3), [0, 0, 0], np.array([0, 0, 1.0])
    camera.fov, camera.width, camera.height, camera.near, camera.far = 50.0, 64, 32, 1.0, 9.0
    assert camera.eye == (1.0, 2.0, 3.0) and camera.up == (0.0, 0.0, 1.0)
    camera.save(tmp_path / "c.json")
    loaded = surftrace.Camera.load(tmp_path / "c.json")
    assert loaded == camera and loaded.fov == 50.0 and (loaded.width, loaded.height) == (64, 32)
    assert json.loads((tmp_path / "c.json").read_text())["fov_y_degrees"] == 50.0


def test_camera_errors(tmp_path):
    with pytest.raises(ValueError, match="no depth range"):
        surftrace.Camera().projection_matrix
    with pytest.raises(ValueError, match="eye"):
        surftrace.Camera(eye=(0, 0))
    with pytest.raises(ValueError, match="projection"):
        surftrace.Camera(projection="fisheye")
    with pytest.raises(ValueError):
        surftrace.Camera(eye=(0, 0, 0), look_at=(0, 0, 0))
    with pytest.raises(ValueError, match=r"\(4, 4\)"):
        surftrace.Camera.from_matrices(10, 10, np.identity(3), np.identity(4))
    with pytest.raises(ValueError, match="finite"):
        surftrace.Camera.from_matrices(10, 10, np.full((4, 4), np.nan), np.identity(4))
    with pytest.raises(FileNotFoundError):
        surftrace.Camera.load(tmp_path / "none.json")
    (tmp_path / "bad.json").write_text('{"width": 3}')
    with pytest.raises(ValueError):
        surftrace.Camera.load(tmp_path / "bad.json")
    with pytest.raises(ValueError):
        surftrace.Camera.from_json("{not json")


# ---- render's arguments ------------------------------------------------------------------------


@pytest.mark.parametrize("options, error, match", [
    (dict(color="rainbow"), ValueError, "color"),
    (dict(spp=0), ValueError, "spp"),
    (dict(spp=2.5), ValueError, "spp"),
    (dict(opacity=1.5), ValueError, "opacity"),
    (dict(opacity=0.0), ValueError, "ball_and_stick"),
    (dict(background=(1, 2, 3)), ValueError, "background"),
    (dict(uniform_color="red"), ValueError, "uniform_color"),
    (dict(size=(0, 10)), ValueError, "width"),
    (dict(size="64x64"), ValueError, "size"),
    (dict(engine="vulkan"), ValueError, "vulkan"),
    (dict(engine="gl", spp=4), ValueError, ""),
    (dict(view="sideways"), ValueError, "sideways"),
    (dict(view=(0, 0, 0)), ValueError, "view"),
    (dict(up=(0, 0, 0)), ValueError, "up"),
    (dict(fov=180), ValueError, "fov"),
    (dict(crease_angle=200), ValueError, "crease_angle"),
    (dict(depth_cue_start=10, depth_cue_end=5), ValueError, "depth_cue_end"),
    (dict(depth_darkening_sigma=8), ValueError, "depth_darkening_sigma_px"),
    (dict(depth_darkening_range=0), ValueError, "depth_darkening_range"),
    (dict(shadow=True), TypeError, "shadow"),
    (dict(camera=surftrace.Camera(), view="left"), ValueError, "view"),
    (dict(camera=surftrace.Camera(width=64, height=64), size=(32, 32)), ValueError, "size"),
])
def test_bad_render_arguments_raise(surface, options, error, match):
    with pytest.raises(error, match=match):
        surftrace.render(surface, **options)
