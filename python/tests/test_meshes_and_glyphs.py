"""Tet meshes, glyph fields and parametric scenes from numpy, their converters, and
marching_cubes against the geometry it must reproduce."""

import gzip
import importlib.util
import os

import numpy as np
import pytest

import tessera

SIZE = (64, 64)


def cube_tets():
    """The unit cube as six tets around its main diagonal, with x + y + z per point."""
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    tets = np.array(
        [[0, 1, 3, 7], [0, 3, 2, 7], [0, 2, 6, 7], [0, 6, 4, 7], [0, 4, 5, 7], [0, 5, 1, 7]]
    )
    return corners, tets, corners.sum(axis=1)


def test_tet_mesh_renders_and_counts(device):
    points, tets, values = cube_tets()
    mesh = tessera.TetMesh(points, tets, point_data={"sum": values})
    assert (mesh.n_points, mesh.n_tets, mesh.scalars) == (8, 6, "sum")
    r = tessera.Renderer(device, "interval")
    r.set_data(mesh)
    image = r.render(camera=(30, 20), size=SIZE)
    background = image[0, 0]
    covered = np.any(image != background, axis=2)
    # The cube covers the middle of the image and not its corners.
    assert covered[SIZE[1] // 2, SIZE[0] // 2] and 0.1 < covered.mean() < 0.9


def test_tet_mesh_from_file_equals_arrays(device, tmp_path):
    points, tets, values = cube_tets()
    path = tmp_path / "cube.vtk"
    lines = ["# vtk DataFile Version 2.0", "cube", "ASCII", "DATASET UNSTRUCTURED_GRID"]
    lines.append(f"POINTS {len(points)} float")
    lines += [" ".join(map(str, p)) for p in points]
    lines.append(f"CELLS {len(tets)} {5 * len(tets)}")
    lines += ["4 " + " ".join(map(str, t)) for t in tets]
    lines.append(f"CELL_TYPES {len(tets)}")
    lines += ["10"] * len(tets)
    lines += [f"POINT_DATA {len(points)}", "SCALARS sum float 1", "LOOKUP_TABLE default"]
    lines += [str(v) for v in values]
    path.write_text("\n".join(lines) + "\n")
    images = []
    for mesh in (tessera.load(path), tessera.TetMesh(points, tets, point_data=values)):
        r = tessera.Renderer(device, "interval")
        r.set_data(mesh)
        images.append(r.render(camera=(30, 20), size=SIZE))
    assert np.array_equal(images[0], images[1])


@pytest.mark.parametrize(
    "points, tets, message",
    [
        (np.zeros((4, 2)), [[0, 1, 2, 3]], r"shape \(N, 3\)"),
        (np.eye(4, 3), [[0, 1, 2, 9]], "uses vertex 9, but there are 4 points"),
        (np.eye(4, 3), [[0, 1, 2, -1]], "uses vertex -1"),
        (np.eye(4, 3), [[0.0, 1, 2, 3]], "float64 is not supported"),
        (np.full((4, 3), np.nan), [[0, 1, 2, 3]], "non-finite"),
    ],
)
def test_bad_meshes_raise(points, tets, message):
    with pytest.raises(tessera.DataError, match=message):
        tessera.TetMesh(points, tets)


def test_point_data_must_fit():
    points, tets, values = cube_tets()
    with pytest.raises(tessera.DataError, match="7 values for 8 items"):
        tessera.TetMesh(points, tets, point_data=values[:7])
    with pytest.raises(tessera.DataError, match="no entry 'temp'"):
        tessera.TetMesh(points, tets, point_data={"sum": values}, scalars="temp")


# One value per tet of cube_tets(): the cube's six tets all share vertices 0 and 7.
CELL_VALUES = np.array([1.0, 4.0, 2.0, 8.0, 3.0, 5.5], np.float32)


def assert_same_image(device, first, second, technique="interval"):
    """Both meshes drawn by `technique` from the same view give the same pixels; returns them."""
    images = []
    for mesh in (first, second):
        r = tessera.Renderer(device, technique)
        r.set_data(mesh)
        images.append(r.render(camera=(30, 20), size=SIZE))
    assert np.array_equal(images[0], images[1])
    return images[0]


def averaged_onto_points(n_points, tets, cell_values):
    """Each point's plain mean of the values of the tets that use it, summed in float64."""
    sums = np.zeros(n_points)
    counts = np.zeros(n_points)
    np.add.at(sums, tets, cell_values.astype(np.float64)[:, None])
    np.add.at(counts, tets, 1)
    return (sums / counts).astype(np.float32)


@pytest.mark.parametrize("technique", ["interval", "shell"])
def test_cell_data_renders_as_its_average_over_the_points(device, technique):
    points, tets, _ = cube_tets()
    averaged = averaged_onto_points(len(points), tets, CELL_VALUES)
    # Vertex 0 is in every tet; the others in two (their mean differs from the global one).
    assert averaged[0] == np.float32(CELL_VALUES.astype(np.float64).mean())
    meshes = (
        tessera.TetMesh(points, tets, cell_data={"pressure": CELL_VALUES}),
        tessera.TetMesh(points, tets, point_data={"pressure": averaged}),
    )
    assert [m.scalars for m in meshes] == ["pressure", "pressure"]
    image = assert_same_image(device, *meshes, technique=technique)
    assert len(np.unique(image.reshape(-1, 4), axis=0)) > 10


def test_bad_cell_data_raises():
    points, tets, values = cube_tets()
    with pytest.raises(tessera.DataError, match="cell_data: 5 values for 6 items"):
        tessera.TetMesh(points, tets, cell_data=CELL_VALUES[:5])
    with pytest.raises(tessera.DataError, match="cell_data: expected 1 dimensions"):
        tessera.TetMesh(points, tets, cell_data=np.ones((6, 2)))
    with pytest.raises(tessera.DataError, match="cell_data: dtype complex128 is not supported"):
        tessera.TetMesh(points, tets, cell_data=np.ones(6, complex))
    with pytest.raises(tessera.DataError, match=r"cell_data\['p'\]: 8 values for 6 items"):
        tessera.TetMesh(points, tets, cell_data={"p": values})
    with pytest.raises(tessera.DataError, match="cell_data has no entry 'temp'"):
        tessera.TetMesh(points, tets, cell_data={"p": CELL_VALUES}, scalars="temp")
    with pytest.raises(tessera.DataError, match="cell_data is an empty dict"):
        tessera.TetMesh(points, tets, cell_data={})
    with pytest.raises(tessera.DataError, match="point_data or cell_data, not both"):
        tessera.TetMesh(points, tets, point_data=values, cell_data=CELL_VALUES)
    with pytest.raises(tessera.DataError, match="without point_data or cell_data"):
        tessera.TetMesh(points, tets, scalars="p")


def test_cell_data_keeps_nan_as_point_data_does():
    points, tets, values = cube_tets()
    with_nan = CELL_VALUES.copy()
    with_nan[2] = np.nan
    # Accepted, like NaN point values; the points of that tet become NaN.
    assert tessera.TetMesh(points, tets, cell_data=with_nan).scalars == "scalars"
    values = values.copy()
    values[3] = np.nan
    assert tessera.TetMesh(points, tets, point_data=values).scalars == "scalars"


class FakeMeshio:
    """The parts of a meshio.Mesh the converter reads."""

    class Block:
        def __init__(self, kind, data):
            self.type, self.data = kind, data

    def __init__(self, points, tets, values):
        self.points = points
        self.cells = [self.Block("triangle", np.zeros((1, 3), int)), self.Block("tetra", tets)]
        self.point_data = {"velocity": np.zeros((len(points), 3)), "sum": values}


class FakeMeshioWithCells(FakeMeshio):
    """A meshio.Mesh with per-cell values only: one array per cell block."""

    def __init__(self, points, tets, cell_values):
        super().__init__(points, tets, None)
        self.point_data = {"velocity": np.zeros((len(points), 3))}
        self.cell_data = {
            "gmsh:physical": [np.array([7]), np.arange(len(tets))],
            "pressure": [np.array([[0.0]]), cell_values[:, None]],
        }


def test_from_meshio_takes_cell_data_without_point_data(device):
    points, tets, _ = cube_tets()
    mesh = tessera.from_meshio(FakeMeshioWithCells(points, tets, CELL_VALUES), scalars="pressure")
    assert (mesh.n_tets, mesh.scalars) == (6, "pressure")
    assert tessera.from_meshio(FakeMeshioWithCells(points, tets, CELL_VALUES)).scalars == (
        "gmsh:physical"
    )
    averaged = averaged_onto_points(len(points), tets, CELL_VALUES)
    assert_same_image(device, mesh, tessera.TetMesh(points, tets, point_data=averaged))
    with pytest.raises(tessera.DataError, match="no one-value-per-point or per-cell array 'temp'"):
        tessera.from_meshio(FakeMeshioWithCells(points, tets, CELL_VALUES), scalars="temp")


@pytest.mark.skipif(importlib.util.find_spec("meshio") is None, reason="meshio absent")
def test_from_meshio_with_cell_data_of_a_real_meshio_mesh(device, tmp_path):
    import meshio

    points, tets, _ = cube_tets()
    written = meshio.Mesh(points, [("tetra", tets)], cell_data={"pressure": [CELL_VALUES]})
    written.write(tmp_path / "cube.vtu")
    read = meshio.read(tmp_path / "cube.vtu")
    assert not read.point_data
    mesh = tessera.from_meshio(read)
    assert mesh.scalars == "pressure"
    averaged = averaged_onto_points(len(points), tets, CELL_VALUES)
    assert_same_image(device, mesh, tessera.TetMesh(points, tets, point_data=averaged))


class FakePyvista:
    """The parts of a pyvista.UnstructuredGrid the converter reads: a triangle (VTK type 5)
    among the tets, vectors only as point data, two cell arrays."""

    class Arrays(dict):
        active_scalars_name = None

    def __init__(self, points, tets, cell_values):
        self.points = points
        self.cells_dict = {5: np.array([[0, 1, 2]]), 10: tets}
        self.celltypes = np.array([10, 10, 10, 5, 10, 10, 10], np.uint8)
        self.point_data = self.Arrays(velocity=np.zeros((len(points), 3)))
        with_triangle = np.insert(cell_values, 3, 100.0)
        self.cell_data = self.Arrays(region=np.arange(7), pressure=with_triangle)
        self.cell_data.active_scalars_name = "pressure"


def test_from_pyvista_takes_the_tets_cell_data(device):
    points, tets, _ = cube_tets()
    mesh = tessera.from_pyvista(FakePyvista(points, tets, CELL_VALUES))
    assert (mesh.n_tets, mesh.scalars) == (6, "pressure")
    assert_same_image(device, mesh, tessera.TetMesh(points, tets, cell_data=CELL_VALUES))
    assert tessera.from_pyvista(FakePyvista(points, tets, CELL_VALUES), scalars="region").scalars == (
        "region"
    )


def test_from_meshio_takes_tetra_and_scalars():
    points, tets, values = cube_tets()
    mesh = tessera.from_meshio(FakeMeshio(points, tets, values))
    assert (mesh.n_tets, mesh.scalars) == (6, "sum")
    surface = FakeMeshio(points, tets, values)
    surface.cells = surface.cells[:1]
    with pytest.raises(tessera.DataError, match="no tetra cells.*triangle"):
        tessera.from_meshio(surface)


def glyph_coefficients():
    """2 x 2 x 1 voxels of order-4 coefficients (15 each); one voxel all zero."""
    coeffs = np.zeros((2, 2, 1, 15), np.float32)
    coeffs[..., 0] = 1.0
    coeffs[0, 0, 0, 3] = 0.4  # an l = 2 term: an elongated glyph
    coeffs[1, 1, 0, :] = 0.0
    return coeffs


def test_glyph_field_matches_the_nifti_file(device, tmp_path):
    coeffs = glyph_coefficients()
    field = tessera.GlyphField(coeffs)
    assert field.n_glyphs == 3
    path = tmp_path / "fit.nii"
    write_nifti(path, coeffs)
    images = []
    for data in (field, tessera.load(f"sh:{path}")):
        r = tessera.Renderer(device, "sh-raytrace")
        r.set_data(data)
        images.append(r.render(camera=(0, 60), size=SIZE))
    assert np.array_equal(images[0], images[1])
    assert len(np.unique(images[0].reshape(-1, 4), axis=0)) > 10


DWI_FIT = os.path.join(
    os.environ.get("TESSERA_DATA")
    or os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "tessera", "data"),
    "dwi", "small_64D_csa8.nii.gz",
)


def read_nifti_float32(path):
    """The float32 samples (X, Y, Z, K) and the sform rows of a gzipped NIfTI-1 file, read
    with numpy alone (the test environment has no nibabel)."""
    raw = gzip.open(path).read()
    dims = np.frombuffer(raw, "<i2", 8, 40)
    assert int(np.frombuffer(raw, "<i2", 1, 70)[0]) == 16, "float32 samples"
    offset = int(np.frombuffer(raw, "<f4", 1, 108)[0])
    shape = tuple(int(d) for d in dims[1 : 1 + dims[0]])
    values = np.frombuffer(raw, "<f4", int(np.prod(shape)), offset).reshape(shape, order="F")
    return values, np.frombuffer(raw, "<f4", 12, 280).reshape(3, 4)


@pytest.mark.skipif(not os.path.exists(DWI_FIT), reason=f"{DWI_FIT} absent (scripts/fetch-dwi.sh)")
def test_glyph_field_of_a_real_dipy_fit_matches_tessera_render_sh(device):
    # DIPY's small_64D fitted to order 8: 10 x 10 x 10 voxels of 2 mm, placed by an sform that
    # turns the grid against the world, so the image shows whether the placement was used.
    coeffs, sform = read_nifti_float32(DWI_FIT)
    assert coeffs.shape == (10, 10, 10, 45)
    images = []
    for data in (tessera.GlyphField(coeffs, affine=sform), tessera.load(f"sh:{DWI_FIT}"),
                 tessera.GlyphField(coeffs, spacing=(2, 2, 2))):
        r = tessera.Renderer(device, "sh-raytrace")
        r.set_data(data)
        images.append(r.render(camera=(30, 40), size=(96, 72)))
    assert np.array_equal(images[0], images[1])
    assert len(np.unique(images[0].reshape(-1, 4), axis=0)) > 100
    # Without the placement the field is seen from elsewhere.
    assert (images[2] != images[0]).any(axis=2).sum() > 1000
    with pytest.raises(tessera.DataError, match="spacing or affine, not both"):
        tessera.GlyphField(coeffs, spacing=(2, 2, 2), affine=sform)
    with pytest.raises(tessera.DataError, match="affine: expected shape"):
        tessera.GlyphField(coeffs, affine=np.eye(3))
    flat = np.array(sform, dtype=np.float64)
    flat[:, 0] = 0
    with pytest.raises(tessera.DataError, match="no length"):
        tessera.GlyphField(coeffs, affine=flat)


def write_nifti(path, values):
    """A NIfTI-1 file of float32 `values` shaped (X, Y, Z, K), spacing 1, no placement."""
    header = bytearray(352)
    header[0:4] = (348).to_bytes(4, "little")
    dims = [4, *values.shape, 1, 1, 1]
    header[40:56] = np.array(dims, "<i2").tobytes()
    header[70:72] = (16).to_bytes(2, "little")
    header[72:74] = (32).to_bytes(2, "little")
    header[76:108] = np.ones(8, "<f4").tobytes()
    header[108:112] = np.array([352], "<f4").tobytes()
    header[344:348] = b"n+1\0"
    path.write_bytes(bytes(header) + values.astype("<f4").tobytes(order="F"))


def test_bad_coefficients_raise():
    with pytest.raises(tessera.DataError, match="7 values per voxel is no SH"):
        tessera.GlyphField(np.ones((2, 2, 2, 7)))
    with pytest.raises(tessera.DataError, match="SH basis 'nope'"):
        tessera.GlyphField(glyph_coefficients(), basis="nope")
    with pytest.raises(tessera.DataError, match="spacing"):
        tessera.GlyphField(glyph_coefficients(), spacing=(1, 0, 1))


def test_scene_renders(device):
    scene = tessera.Scene("param:sh-glyphs:2x2:order4")
    assert scene.n_objects == 4
    r = tessera.Renderer(device, "param-points")
    r.set_data(scene)
    image = r.render(size=SIZE)
    assert len(np.unique(image.reshape(-1, 4), axis=0)) > 10
    assert r.stats["patches"] > 0


def ball(n=20, radius=7.0):
    x, y, z = np.meshgrid(*(np.arange(n, dtype=np.float32),) * 3, indexing="ij")
    c = (n - 1) / 2
    return np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2), radius


def area(verts, faces):
    a, b, c = (verts[faces[:, i]] for i in range(3))
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()


def canonical_triangles(verts, faces, quantum=1e-4):
    """The triangles as a sorted list of corner tuples, each rotated (not mirrored) to start
    at its smallest corner: equal for equal surfaces whatever the vertex numbering."""
    corners = np.round(verts[faces] / quantum).astype(np.int64)
    out = []
    for tri in corners:
        tri = [tuple(c) for c in tri]
        first = min(range(3), key=lambda i: tri[i])
        out.append(tuple(tri[first:] + tri[:first]))
    return sorted(out)


def test_marching_cubes_shapes_and_geometry(device):
    distance, radius = ball()
    verts, faces, normals, values = tessera.marching_cubes(distance, radius, device=device)
    assert verts.shape[1] == 3 and faces.shape[1] == 3 and normals.shape == verts.shape
    assert values.shape == (len(verts),) and faces.min() >= 0 and faces.max() < len(verts)
    # Every vertex on the sphere (linear interpolation errs inwards by a fraction of a voxel).
    centre = (distance.shape[0] - 1) / 2
    r = np.linalg.norm(verts - centre, axis=1)
    assert np.all(np.abs(r - radius) < 0.1), (r.min(), r.max())
    assert abs(area(verts, faces) / (4 * np.pi * radius**2) - 1) < 0.02
    # Normals point to lower values: inwards here, where the distance falls.
    assert np.all(np.einsum("ij,ij->i", normals, verts - centre) < 0)
    # The largest sample of each vertex's cell is at or above the level.
    assert np.all(values >= radius)
    # Spacing scales the vertices, as scikit-image's does.
    scaled, faces2, _, _ = tessera.marching_cubes(
        distance, radius, spacing=(1, 2, 3), device=device
    )
    # (GPU blocks finish in any order, so vertices are compared sorted.)
    assert len(faces) == len(faces2)
    expected = verts * [1, 2, 3]
    assert np.allclose(scaled[np.lexsort(scaled.T)], expected[np.lexsort(expected.T)], atol=1e-4)


@pytest.mark.skipif(importlib.util.find_spec("skimage") is None, reason="scikit-image absent")
def test_marching_cubes_area_agrees_with_scikit_image():
    from skimage.measure import marching_cubes as skimage_mc

    distance, radius = ball(32, 11.3)
    verts, faces, _, _ = tessera.marching_cubes(distance, radius, method="cpu")
    sk_verts, sk_faces, _, _ = skimage_mc(distance, radius)
    # Same edge intersections; the tables split ambiguous cells differently, which moves
    # the area by far less than this on a smooth surface.
    assert abs(area(verts, faces) / area(sk_verts, sk_faces) - 1) < 0.005


@pytest.mark.parametrize(
    "method,path", [("meshlets", "compute"), ("meshlets", "mesh"), ("pmb", "auto"), ("pmb:4x4x4", "auto")]
)
def test_gpu_extraction_gives_the_cpu_surface(device, method, path):
    caps = tessera.info(device)["capabilities"]
    if path == "mesh" and not caps.get("mesh_shader"):
        pytest.skip("task/mesh extraction: the device has no VK_EXT_mesh_shader")
    x, y, z = np.meshgrid(*(np.arange(n, dtype=np.float32) for n in (23, 17, 14)), indexing="ij")
    gyroid = np.sin(0.55 * x) * np.cos(0.55 * y) + np.sin(0.55 * y) * np.cos(0.55 * z)
    gyroid += np.sin(0.55 * z) * np.cos(0.55 * x)
    for dtype in (np.float32, np.float64):
        field = gyroid.astype(dtype)
        gpu = tessera.marching_cubes(field, 0.1037, spacing=(1, 1.5, 0.75), method=method,
                                     path=path, device=device)
        cpu = tessera.marching_cubes(field, 0.1037, spacing=(1, 1.5, 0.75), method="cpu")
        # Welded: one vertex per crossed edge, as the CPU's.
        assert len(gpu[0]) == len(cpu[0]) and len(gpu[1]) == len(cpu[1]) > 500
        assert canonical_triangles(gpu[0], gpu[1]) == canonical_triangles(cpu[0], cpu[1])
        # Per vertex, the same normal and cell maximum wherever the vertex is numbered.
        order_gpu = np.lexsort(gpu[0].T)
        order_cpu = np.lexsort(cpu[0].T)
        assert np.array_equal(gpu[0][order_gpu], cpu[0][order_cpu])
        assert np.allclose(gpu[2][order_gpu], cpu[2][order_cpu], atol=1e-6)
        assert np.array_equal(gpu[3][order_gpu], cpu[3][order_cpu])


T1_TEMPLATE = "/usr/share/mricron/templates/ch2.nii.gz"


@pytest.mark.skipif(importlib.util.find_spec("skimage") is None, reason="scikit-image absent")
@pytest.mark.skipif(not os.path.exists(T1_TEMPLATE), reason=f"{T1_TEMPLATE} absent (mricron-data)")
def test_marching_cubes_of_a_real_scan_agrees_with_scikit_image(device):
    from skimage.measure import marching_cubes as skimage_mc

    scan = tessera.load(T1_TEMPLATE)
    samples = scan.to_numpy()
    assert samples.shape == scan.shape and samples.dtype == np.dtype(scan.dtype)
    lo, hi = scan.value_range
    level = np.floor(lo + 0.4 * (hi - lo)) + 0.5
    verts, faces, _, _ = tessera.marching_cubes(samples, level, device=device)
    sk_verts, sk_faces, _, _ = skimage_mc(samples.astype(np.float32), level)
    # The same edge crossings (so the same vertices); the two case tables split ambiguous
    # cells differently, which on this noisy scan moves the area by about a tenth of a
    # percent; 0.5 % is far below what a wrong surface would change.
    assert len(faces) > 100_000
    assert abs(area(verts, faces) / area(sk_verts, sk_faces) - 1) < 0.005
    assert abs(len(verts) / len(sk_verts) - 1) < 0.001


def test_marching_cubes_refuses_what_it_cannot_do():
    distance, radius = ball()
    with pytest.raises(tessera.DataError, match="method 'pmbx'"):
        tessera.marching_cubes(distance, radius, method="pmbx")
    with pytest.raises(tessera.DataError, match="no 'mesh' path"):
        tessera.marching_cubes(distance, radius, method="cpu", path="mesh")
    with pytest.raises(tessera.DataError, match="not a number"):
        tessera.marching_cubes(distance, float("nan"), method="cpu")


def test_shell_traversal_layouts_draw_the_same_image(device):
    points, tets, values = cube_tets()
    mesh = tessera.TetMesh(points, tets, point_data=values)
    images = []
    for layout in ("tet32", "tet20", "tet16"):
        r = tessera.Renderer(device, "shell", layout=layout)
        r.set_data(mesh)
        images.append(r.render(camera=(30, 20), size=SIZE))
        assert r.stats["technique"] == "shell"
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])
    assert np.any(images[0] != images[0][0, 0], axis=2).mean() > 0.1
    with pytest.raises(tessera.DataError, match="tet64"):
        tessera.Renderer(device, "shell", layout="tet64")


def test_shell_effects_are_renderer_options(device):
    points, tets, values = cube_tets()
    mesh = tessera.TetMesh(points, tets, point_data=values)
    plain = tessera.Renderer(device, "shell")
    plain.set_data(mesh)
    before = plain.render(camera=(30, 20), size=SIZE)
    for options in (
        {"shadows": True},
        {"shadows": True, "light_dir": (1, 2, 0)},
        {"ao": 4, "ao_radius": 0.2},
        {"gradient": True},
    ):
        r = tessera.Renderer(device, "shell", **options)
        r.set_data(mesh)
        image = r.render(camera=(30, 20), size=SIZE)
        assert not np.array_equal(image, before), options
    with pytest.raises(tessera.DataError, match="shadows=True"):
        tessera.Renderer(device, "shell", light=(1, 2, 3))
    with pytest.raises(tessera.DataError, match="1 to 64"):
        tessera.Renderer(device, "shell", ao=0)
