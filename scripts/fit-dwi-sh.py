"""Fits SH coefficients to DIPY's small_64D diffusion scan (10x10x10 voxels, 64 directions) and
saves them as a 4-D NIfTI: CSA ODF model, order 8 (45 coefficients), DIPY's default basis
(descoteaux07 with legacy=True). Usage: fit-dwi-sh.py OUT.nii.gz"""
import sys

import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.data import get_fnames
from dipy.io.gradients import read_bvals_bvecs
from dipy.reconst.shm import CsaOdfModel

fdata, fbval, fbvec = get_fnames(name="small_64D")
image = nib.load(fdata)
bvals, bvecs = read_bvals_bvecs(str(fbval), str(fbvec))
model = CsaOdfModel(gradient_table(bvals, bvecs=bvecs), sh_order_max=8)
coefficients = model.fit(image.get_fdata()).shm_coeff.astype(np.float32)
nib.save(nib.Nifti1Image(coefficients, image.affine), sys.argv[1])
print(f"{sys.argv[1]}: {coefficients.shape}")
