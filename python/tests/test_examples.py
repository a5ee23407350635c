"""The scripts in examples/python run and write their images (each in a fresh folder)."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "python"
T1_TEMPLATE = "/usr/share/mricron/templates/ch2.nii.gz"


def run(script, out, *args):
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / script), str(out), *args],
        cwd=EXAMPLES,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def images(out):
    found = sorted(out.glob("*.png"))
    for path in found:
        assert path.stat().st_size > 1000, path
    return found


def test_iso_sweep_writes_one_image_per_isovalue(tmp_path):
    text = run("iso_sweep.py", tmp_path)
    assert len(images(tmp_path)) == 5
    assert text.count(" triangles, ") == 5


def test_tet_mesh_renders_with_both_techniques(tmp_path):
    run("tet_mesh.py", tmp_path)
    assert [p.name for p in images(tmp_path)] == ["tets-interval.png", "tets-shell.png"]


@pytest.mark.skipif(importlib.util.find_spec("meshio") is None, reason="meshio absent")
def test_tet_mesh_reads_a_meshio_file(tmp_path):
    import meshio

    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    mesh = meshio.Mesh(points, [("tetra", np.array([[0, 1, 2, 3]]))], point_data={"v": np.arange(4.0)})
    path = tmp_path / "one.vtu"
    meshio.write(path, mesh)
    text = run("tet_mesh.py", tmp_path / "out", str(path))
    assert "TetMesh(4 points, 1 tets)" in text and len(images(tmp_path / "out")) == 2


@pytest.mark.skipif(not os.path.exists(T1_TEMPLATE), reason=f"{T1_TEMPLATE} absent (mricron-data)")
def test_render_nifti_writes_three_isovalues(tmp_path):
    run("render_nifti.py", tmp_path)
    assert len(images(tmp_path)) == 3


@pytest.mark.skipif(importlib.util.find_spec("dipy") is None, reason="dipy absent")
def test_dipy_glyphs_renders_a_fitted_slice(tmp_path):
    text = run("dipy_glyphs.py", tmp_path)
    assert "GlyphField(100 glyphs)" in text and len(images(tmp_path)) == 1
