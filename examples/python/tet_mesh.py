"""Render a tetrahedral mesh read by meshio (or PyVista) with interval shading and with shell
traversal.

    python tet_mesh.py [OUT_DIR] [MESH]

MESH is any file meshio reads with tetra cells (VTU, Gmsh, TetGen's .node/.ele, ...); by
default a small generated box. Needs `pip install meshio` for files.
"""

import sys
from pathlib import Path

import numpy as np

import tessera
from _show import save

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

if len(sys.argv) > 2:
    import meshio

    mesh = tessera.from_meshio(meshio.read(sys.argv[2]), name=Path(sys.argv[2]).name)
else:
    # A 6x6x6 grid of cubes, six tets each, with a radial scalar per point.
    n = 6
    grid = np.stack(np.meshgrid(*(np.arange(n + 1.0),) * 3, indexing="ij"), -1).reshape(-1, 3)
    index = np.arange((n + 1) ** 3).reshape((n + 1,) * 3)
    cubes = [
        [index[x + dx, y + dy, z + dz] for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)]
        for x in range(n) for y in range(n) for z in range(n)
    ]
    around = [[0, 1, 3, 7], [0, 3, 2, 7], [0, 2, 6, 7], [0, 6, 4, 7], [0, 4, 5, 7], [0, 5, 1, 7]]
    tets = np.array([[c[i] for i in t] for c in cubes for t in around])
    radius = np.linalg.norm(grid - n / 2, axis=1)
    mesh = tessera.TetMesh(grid, tets, point_data={"radius": radius}, name="box")
print(mesh)

device = tessera.Device()
for technique in ("interval", "shell"):
    renderer = tessera.Renderer(device, technique)
    renderer.set_data(mesh)
    image = renderer.render(camera=(30, 20, 2.2), size=(640, 480))
    save(image, out / f"tets-{technique}.png")
    print(f"  {technique}: {renderer.stats}")
