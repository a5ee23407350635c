"""Tessera: volumes, tetrahedral meshes and glyph fields rendered on the GPU from numpy.

    import numpy as np, tessera
    device = tessera.Device()
    volume = tessera.Volume(np.load("ct.npy"), spacing=(0.7, 0.7, 1.25))
    r = tessera.Renderer(device, "direct")
    r.set_data(volume)
    image = r.render(camera=(30, 20), size=(800, 600), iso=300)   # (600, 800, 4) uint8
    verts, faces, normals, values = tessera.marching_cubes(volume, 300, device=device)

Arrays are indexed ``[x, y, z]`` as nibabel and scikit-image index them. Errors are
``tessera.DataError`` (input) and ``tessera.GpuError`` (device), both ``TesseraError``.
"""

import json as _json

from ._tessera import (
    DataError,
    Device,
    GlyphField,
    GpuError,
    Renderer,
    Scene,
    TesseraError,
    TetMesh,
    Volume,
    _bench,
    devices,
    load,
    marching_cubes,
)
from .convert import from_meshio, from_pyvista

__all__ = [
    "DataError",
    "Device",
    "GlyphField",
    "GpuError",
    "Renderer",
    "Scene",
    "TesseraError",
    "TetMesh",
    "Volume",
    "bench",
    "devices",
    "from_meshio",
    "from_pyvista",
    "info",
    "load",
    "marching_cubes",
]


def info(device=None):
    """The devices present and what ``device`` (default: the best one) can do, as a dict."""
    if device is None:
        device = Device()
    return {
        "devices": [
            {"index": index, "name": name, "type": kind} for index, name, kind in devices()
        ],
        "device": device.name,
        "capabilities": _json.loads(device._capabilities_json()),
    }


def bench(scenario, device=None, **options):
    """Runs one of ``tessera bench``'s scenarios (``"isosurface"``, ``"iso-sweep"``,
    ``"extraction"``, ``"interval"``, ...) and returns its records as dicts: technique, path,
    dataset, image size, GPU-timestamp medians per stage (``stages``) and counters
    (``counts``). Options: ``quick`` (small data, for CPU drivers), ``frames``, ``warmup`` (at
    least; more until frame times settle, up to 200 in all, except with ``quick``),
    ``iso_fraction``, ``data`` (a volume file or spec instead of the built-in phantoms),
    ``sizes`` (a list of ``(width, height)``), ``keep_busy_ms`` (GPU milliseconds each frame
    plus an arithmetic-only dispatch after it take, so that the GPU's clocks stay up between
    frames as in a render loop; 2 by default, 0 for idle gaps), ``techniques`` (for
    ``"isosurface"`` and ``"iso-sweep"``: the record names to time besides ray marching, e.g.
    ``["direct+hzb"]``), ``paths`` (``["graphics"]``, ``["compute"]`` or both), ``variants``
    and ``ablations`` (as ``tessera bench``'s ``--variants`` and ``--ablations``). Notes the
    scenario makes are printed."""
    if device is None:
        device = Device()
    records, notes = _bench(device, scenario, **options)
    for note in notes:
        print(f"note: {note}")
    return [_json.loads(line) for line in records]
