"""Volumes from numpy arrays: every dtype and memory order gives the same image as the same
samples read from a file, isovalues change without re-uploading, bad arrays raise."""

import numpy as np
import pytest

import tessera

SIZE = (96, 80)


def sphere(n=24, dtype=np.float32):
    """Distance from the centre, indexed [x, y, z], scaled so that integer types keep it."""
    x, y, z = np.meshgrid(*(np.arange(n, dtype=np.float64),) * 3, indexing="ij")
    c = (n - 1) / 2
    d = np.sqrt((x - c) ** 2 + (y - 1.3 * c) ** 2 + (z - c) ** 2)
    return np.round(d * 4).astype(dtype)


def render(device, volume, technique="direct", **look):
    r = tessera.Renderer(device, technique)
    r.set_data(volume)
    return r.render(camera=(30, 20), size=SIZE, **look)


def test_every_dtype_and_order_gives_the_file_image(device, tmp_path):
    samples = sphere()
    # x fastest on disk, as the raw loader reads it.
    path = tmp_path / "sphere.raw"
    samples.transpose(2, 1, 0).tofile(path)
    from_file = tessera.load(path, dims=samples.shape, dtype="float32")
    assert isinstance(from_file, tessera.Volume)
    expected = render(device, from_file, iso=30.0)
    assert expected.shape == (SIZE[1], SIZE[0], 4) and expected.dtype == np.uint8
    # The surface is there: not every pixel is background.
    assert len(np.unique(expected.reshape(-1, 4), axis=0)) > 10
    for dtype in (np.float32, np.float64, np.int16, np.int32):
        for order in ("C", "F"):
            array = np.asarray(samples.astype(dtype), order=order)
            got = render(device, tessera.Volume(array), iso=30.0)
            assert np.array_equal(got, expected), (dtype, order)
    # uint8 and uint16 stay integer on the GPU: the same surface as float32.
    for dtype in (np.uint8, np.uint16):
        got = render(device, tessera.Volume(samples.astype(dtype)), iso=30.0)
        assert np.array_equal(got, expected), dtype


def test_transposed_array_is_a_different_volume(device):
    samples = sphere()
    a = render(device, tessera.Volume(samples), iso=30.0)
    b = render(device, tessera.Volume(np.ascontiguousarray(samples.transpose(1, 0, 2))), iso=30.0)
    assert not np.array_equal(a, b)


def test_new_isovalue_renders_without_upload(device):
    r = tessera.Renderer(device, "direct")
    r.set_data(tessera.Volume(sphere()))
    first = r.render(size=SIZE, iso=30.0)
    second = r.render(size=SIZE, iso=40.0)
    assert not np.array_equal(first, second)
    again = r.render(size=SIZE, iso=30.0)
    assert np.array_equal(first, again)
    stats = r.stats
    assert stats["data_uploads"] == 1 and stats["pipeline_builds"] == 1, stats
    assert stats["triangles"] > 0 and stats["gpu_ms"] >= 0


def test_properties():
    v = tessera.Volume(sphere(dtype=np.uint16), spacing=(1, 1, 2.5), name="ct")
    assert v.shape == (24, 24, 24) and v.spacing == (1, 1, 2.5)
    assert v.dtype == "uint16" and v.name == "ct"
    assert v.value_range[0] >= 0 and v.value_range[1] > 50


@pytest.mark.parametrize(
    "array, message",
    [
        (np.zeros((4, 4)), "expected 3 dimensions"),
        (np.zeros((0, 4, 4)), "empty"),
        (np.zeros((4, 4, 4), dtype=complex), "complex128"),
        (np.full((4, 4, 4), np.nan, dtype=np.float32), "non-finite .* nan_fill=VALUE"),
        (np.zeros((1, 4, 4), dtype=np.float32), "1x4x4"),
        ("text", "expected 3 dimensions, got 0"),
    ],
)
def test_bad_arrays_raise_data_error(array, message):
    with pytest.raises(tessera.DataError, match=message):
        tessera.Volume(array)


def test_nan_fill():
    a = sphere()
    a[0, 0, 0] = np.nan
    assert tessera.Volume(a, nan_fill=0.0).value_range[0] == 0.0


def test_a_renderer_survives_errors(device):
    r = tessera.Renderer(device, "direct")
    with pytest.raises(tessera.DataError, match="before set_data"):
        r.render(size=SIZE)
    with pytest.raises(tessera.DataError, match="draws volumes"):
        r.set_data(tessera.Scene("param:sphere"))
    r.set_data(tessera.Volume(sphere()))
    with pytest.raises(tessera.DataError, match="camera"):
        r.render(camera=(1, 2, 3, 4), size=SIZE)
    with pytest.raises(tessera.DataError, match="empty"):
        r.render(size=(0, 10))
    assert r.render(size=SIZE, iso=30.0).shape == (SIZE[1], SIZE[0], 4)


def test_pmb_block_sizes_draw_the_same_surface(device):
    volume = tessera.Volume(sphere())
    images = []
    for block in ("4x4x4", "8x8x8"):
        r = tessera.Renderer(device, "pmb", path="compute", pmb_block=block)
        r.set_data(volume)
        images.append(r.render(camera=(30, 20), size=SIZE, iso=30.0))
        assert r.stats["triangles"] > 0
    # The same triangles in other blocks: pixels differ only where two tie in depth.
    differ = np.any(images[0] != images[1], axis=2).mean()
    assert differ < 0.002, differ
    with pytest.raises(tessera.DataError, match="8x8x2"):
        tessera.Renderer(device, "pmb", pmb_block="8x8x2")


def test_culling_choices_draw_the_same_image(device):
    volume = tessera.Volume(sphere())
    images = []
    for culling in (True, False, "auto", "on", "off"):
        r = tessera.Renderer(device, "direct", path="compute", culling=culling)
        r.set_data(volume)
        images.append(r.render(camera=(30, 20), size=SIZE, iso=30.0))
    for image in images[1:]:
        assert np.array_equal(images[0], image)
    with pytest.raises(tessera.DataError, match="culling 'sometimes'"):
        tessera.Renderer(device, "direct", culling="sometimes")


def test_drawing_the_hidden_side_draws_the_same_image(device):
    volume = tessera.Volume(sphere())
    images = []
    for hidden_side, one_side in (("skip", 1), ("draw", 0)):
        r = tessera.Renderer(device, "direct", path="compute", hidden_side=hidden_side)
        r.set_data(volume)
        images.append(r.render(camera=(30, 20), size=SIZE, iso=30.0))
        assert r.stats["one_side_drawn"] == one_side, hidden_side
    assert np.array_equal(images[0], images[1])
    with pytest.raises(tessera.DataError, match="hidden side 'both'"):
        tessera.Renderer(device, "direct", hidden_side="both")


def test_unknown_names_raise():
    with pytest.raises(tessera.DataError, match="unknown technique"):
        tessera.Renderer(tessera.Device(), "nope")
    with pytest.raises(tessera.DataError, match="No such file|nothing.nrrd"):
        tessera.load("nothing.nrrd")




def test_bench_returns_the_scenario_records(device):
    records = tessera.bench(
        "raymarch", device=device, frames=3, warmup=1, data="procedural:sphere:24",
        sizes=[(48, 32), (64, 40)],
    )
    assert [(r["width"], r["height"]) for r in records] == [(48, 32), (64, 40)]
    for r in records:
        assert (r["scenario"], r["technique"], r["frames"]) == ("raymarch", "raymarch", 3)
        assert r["dataset"].startswith("sphere_24")
        assert r["stages"][0]["median_ms"] > 0 and r["counts"]["mrays_per_s"] > 0
        # At least the warm-up asked for; more only while frame times had not settled.
        assert 1 <= r["stages"][0]["warmup_frames"] <= 200
        # The GPU kept loaded between frames, by default.
        assert r["keep_busy_ms"] == 2.0
    idle = tessera.bench(
        "raymarch", device=device, frames=2, warmup=1, data="procedural:sphere:24",
        sizes=[(48, 32)], keep_busy_ms=0.0,
    )
    assert [r["keep_busy_ms"] for r in idle] == [0.0]
    with pytest.raises(tessera.DataError, match="keep_busy_ms"):
        tessera.bench("raymarch", device=device, keep_busy_ms=-1.0)
    with pytest.raises(tessera.DataError, match="unknown scenario"):
        tessera.bench("nothing", device=device)
    with pytest.raises(tessera.DataError, match="frames"):
        tessera.bench("raymarch", device=device, frames=0)


def test_bench_times_only_the_techniques_asked_for(device):
    records = tessera.bench(
        "isosurface", device=device, frames=2, warmup=1, data="procedural:sphere:24",
        sizes=[(48, 32)], techniques=["direct+hzb"],
    )
    assert sorted({r["technique"] for r in records}) == ["direct+hzb", "raymarch"]
    with pytest.raises(tessera.DataError, match=r"no isosurface technique 'direct\+nothing'"):
        tessera.bench("isosurface", device=device, quick=True, techniques=["direct+nothing"])
    with pytest.raises(tessera.DataError, match="techniques"):
        tessera.bench("raymarch", device=device, techniques=["direct"])


def test_bench_takes_paths_and_variants(device):
    records = tessera.bench(
        "isosurface", device=device, frames=2, warmup=1, data="procedural:sphere:24",
        sizes=[(48, 32)], techniques=["direct"], paths=["compute"], variants="hidden-side",
    )
    drawn = sorted((r["technique"], r["path"], r.get("variant", "")) for r in records)
    assert drawn == [
        ("direct", "compute", ""),
        ("direct", "compute", "hidden side drawn"),
        ("raymarch", "compute", ""),
    ]
    with pytest.raises(tessera.DataError, match="choose graphics or compute"):
        tessera.bench("isosurface", device=device, paths=["auto"])
    with pytest.raises(tessera.DataError, match="variants"):
        tessera.bench("raymarch", device=device, variants="hidden-side")
