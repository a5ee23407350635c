"""``render(dtype="float32")``: the float quantity interval shading accumulates, and the
radiance shell traversal composites, of which the uint8 image is the quantized colour."""

import numpy as np
import pytest

import tessera

SIZE = (64, 48)
BACKGROUND = (1.0, 0.75, 0.5)


def cube():
    """The unit cube as six tets around its main diagonal, with x + y + z per point."""
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    tets = np.array(
        [[0, 1, 3, 7], [0, 3, 2, 7], [0, 2, 6, 7], [0, 6, 4, 7], [0, 4, 5, 7], [0, 5, 1, 7]]
    )
    return tessera.TetMesh(corners, tets, point_data=corners.sum(axis=1))


def quantized(light):
    """What the composite pass stores: each channel clamped to [0, 1], times 255, rounded."""
    return np.round(np.clip(light, 0.0, 1.0) * 255.0)


def render_both(renderer, **look):
    background = ",".join(map(str, BACKGROUND))
    colour = renderer.render(camera=(30, 20), size=SIZE, background=background, **look)
    values = renderer.render(
        camera=(30, 20), size=SIZE, background=background, dtype="float32", **look
    )
    assert colour.dtype == np.uint8 and colour.shape == (SIZE[1], SIZE[0], 4)
    assert values.dtype == np.float32 and values.shape == (SIZE[1], SIZE[0], 3)
    assert renderer.quantity in ("optical-depth", "emission", "maximum", "radiance")
    return colour, values


@pytest.mark.parametrize("integrate", ["absorption", "tet-absorption"])
def test_optical_depth_quantizes_to_the_colour_image(device, integrate):
    r = tessera.Renderer(device, "interval")
    r.set_data(cube())
    colour, depth = render_both(r, integrate=integrate, density=2.0)
    # Rays through the cube's middle cross some depth; the corners of the image none.
    assert depth[SIZE[1] // 2, SIZE[0] // 2].min() > 0.05 and np.all(depth[0, 0] == 0)
    assert 0.1 < np.any(depth > 0, axis=2).mean() < 0.9
    # Beer-Lambert: the background light that gets through is exp(-depth) of it.
    expected = quantized(np.asarray(BACKGROUND) * np.exp(-depth.astype(np.float64)))
    # exp() on the GPU and in numpy differ in the last bits: a value on a rounding edge
    # may land one step away.
    assert np.abs(colour[..., :3] - expected).max() <= 1
    assert np.mean(colour[..., :3] != expected) < 0.01
    assert np.all(colour[..., 3] == 255)


def test_emission_adds_to_the_background(device):
    r = tessera.Renderer(device, "interval")
    r.set_data(cube())
    colour, light = render_both(r, integrate="emission")
    assert light.max() > 0.01
    expected = quantized(np.asarray(BACKGROUND) + light.astype(np.float64))
    assert np.abs(colour[..., :3] - expected).max() <= 1


@pytest.mark.parametrize("path", ["compute", "graphics"])
def test_shell_radiance_quantizes_to_the_colour_image(device, path):
    r = tessera.Renderer(device, "shell", path=path)
    try:
        r.set_data(cube())
    except tessera.DataError as e:
        if "needs features" not in str(e):
            raise
        pytest.skip(f"shell traversal's {path} path: {e}")
    assert r.quantity is None
    colour, light = render_both(r, density=4.0)
    assert r.quantity == "radiance"
    # The colour is the radiance clamped and rounded, the background where no tet is.
    assert np.array_equal(colour[..., :3], quantized(light.astype(np.float64)))
    assert np.allclose(light[0, 0], BACKGROUND)
    assert np.abs(light - np.asarray(BACKGROUND, np.float32)).max() > 0.05


def test_float_images_only_where_a_technique_has_them(device):
    volume = tessera.Volume(np.arange(4 * 4 * 4, dtype=np.float32).reshape(4, 4, 4))
    r = tessera.Renderer(device, "raymarch")
    r.set_data(volume)
    assert r.render(size=SIZE, dtype=np.uint8).dtype == np.uint8
    with pytest.raises(tessera.DataError, match="raymarch draws colours only"):
        r.render(size=SIZE, dtype="float32")
    with pytest.raises(tessera.DataError, match="dtype float64: images are uint8"):
        r.render(size=SIZE, dtype=np.float64)
    with pytest.raises(tessera.DataError, match="dtype"):
        r.render(size=SIZE, dtype="no such type")
