#!/usr/bin/env python3
"""Isosurface areas from VTK, the reference numbers of tessera-data's VTK comparison tests.

Needs only PyPI's vtk and numpy (python3 -m venv /tmp/vtk && /tmp/vtk/bin/pip install vtk numpy).
  vtk-marching-cubes.py --diagonal-cell
  vtk-marching-cubes.py brainsmall.den 40.5 80.5 120.5   (62-byte header, 128x128x84 u8)
  vtk-marching-cubes.py ch2.nii.gz 50.5 80.5 110.5
Prints, per isovalue and filter, the total area and the non-degenerate triangle count.
"""
import sys
import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy


def image(values, dims, spacing=(1.0, 1.0, 1.0)):
    img = vtk.vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(*spacing)
    img.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(values).ravel(), deep=1))
    return img


def measure(img, iso, filter_class):
    f = filter_class()
    f.SetInputData(img)
    f.SetValue(0, iso)
    f.ComputeNormalsOff()
    f.Update()
    out = f.GetOutput()
    if out.GetNumberOfPolys() == 0:
        return 0.0, 0
    p = vtk_to_numpy(out.GetPoints().GetData()).astype(np.float64)
    t = vtk_to_numpy(out.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a = 0.5 * np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]), axis=1)
    return a.sum(), int((a > 0).sum())


def load(path):
    if path.endswith(".den"):
        raw = np.fromfile(path, dtype=np.uint8)[62:]
        return image(raw, (128, 128, 84))
    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


if sys.argv[1] == "--diagonal-cell":
    # 2x2x2 float32, 1 at corners (0,0,0) and (1,1,0), 0 elsewhere; x fastest.
    img = image(np.array([1, 0, 0, 1, 0, 0, 0, 0], dtype=np.float32), (2, 2, 2))
    isos = [0.2, 0.8]
else:
    img = load(sys.argv[1])
    isos = [float(v) for v in sys.argv[2:]]
print("vtk", vtk.vtkVersion.GetVTKVersion(), "dims", img.GetDimensions(), "spacing", img.GetSpacing())
for iso in isos:
    for name, cls in (("vtkMarchingCubes", vtk.vtkMarchingCubes), ("vtkFlyingEdges3D", vtk.vtkFlyingEdges3D)):
        area, tris = measure(img, iso, cls)
        print(f"iso {iso}: {name}: area {area:.7g}, {tris} non-degenerate triangles")
