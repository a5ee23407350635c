"""Fit a constant-solid-angle ODF model to DIPY's small_64D diffusion scan and render its
spherical-harmonic glyphs.

    python dipy_glyphs.py [OUT_DIR]

Needs `pip install dipy` (it downloads small_64D, a few MB, on first use).
"""

import sys
from pathlib import Path

import tessera
from _show import save

from dipy.core.gradients import gradient_table
from dipy.data import get_fnames
from dipy.io.image import load_nifti
from dipy.io.gradients import read_bvals_bvecs
from dipy.reconst.shm import CsaOdfModel

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

dwi, bvals, bvecs = get_fnames("small_64D")
data, affine = load_nifti(dwi)
bval_list, bvec_list = read_bvals_bvecs(bvals, bvecs)
gtab = gradient_table(bval_list, bvecs=bvec_list)
fit = CsaOdfModel(gtab, sh_order_max=8).fit(data[:, :, data.shape[2] // 2 : data.shape[2] // 2 + 1])
coeffs = fit.shm_coeff  # (X, Y, 1, 45), DIPY's descoteaux07 basis

device = tessera.Device()
glyphs = tessera.GlyphField(coeffs, basis="descoteaux07")
print(glyphs)
renderer = tessera.Renderer(device, "param-points")
renderer.set_data(glyphs)
image = renderer.render(camera=(0, 0, 1.6), size=(800, 800))
save(image, out / "dipy-glyphs.png")
print(f"  {renderer.stats}")
