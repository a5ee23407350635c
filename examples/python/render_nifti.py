"""Render a NIfTI (or NRRD, raw, VTI) volume's isosurfaces at a few isovalues.

    python render_nifti.py [OUT_DIR] [VOLUME]

VOLUME defaults to the MNI ch2 template of the Debian package mricron-data.
"""

import sys
from pathlib import Path

import tessera
from _show import save

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
path = sys.argv[2] if len(sys.argv) > 2 else "/usr/share/mricron/templates/ch2.nii.gz"
out.mkdir(parents=True, exist_ok=True)

device = tessera.Device()
volume = tessera.load(path)  # spacing and orientation from the header
print(volume, "spacing", volume.spacing, "values", volume.value_range)
renderer = tessera.Renderer(device, "direct")
renderer.set_data(volume)  # uploaded once; the isovalues below reuse it
for fraction in (0.25, 0.4, 0.6):
    image = renderer.render(camera=(120, 20, 1.8), size=(640, 480), iso_fraction=fraction)
    save(image, out / f"nifti-iso{int(fraction * 100)}.png")
    print(f"  iso fraction {fraction}: {renderer.stats}")
