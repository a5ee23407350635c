"""Explore isovalues: for each, extract the isosurface on the GPU (as meshlets, welded, as
scikit-image's marching_cubes returns it) and render it, writing one PNG per isovalue.

    python iso_sweep.py [OUT_DIR]
"""

import sys
from pathlib import Path

import numpy as np

import tessera
from _show import save

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

# A gyroid-like field, indexed [x, y, z] as scikit-image and nibabel index volumes.
x, y, z = np.meshgrid(*(np.linspace(0, 4 * np.pi, 64, dtype=np.float32),) * 3, indexing="ij")
field = np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)

device = tessera.Device()
volume = tessera.Volume(field, spacing=(1, 1, 1))
renderer = tessera.Renderer(device, "meshlets")  # extracts again whenever the isovalue moves
renderer.set_data(volume)
for level in np.linspace(-1.0, 1.0, 5):
    verts, faces, normals, values = tessera.marching_cubes(volume, level, device=device)
    image = renderer.render(camera=(30, 25, 1.9), size=(480, 480), iso=float(level))
    save(image, out / f"sweep-{level:+.2f}.png")
    print(f"  level {level:+.2f}: {len(faces)} triangles, {len(verts)} vertices; {renderer.stats}")
