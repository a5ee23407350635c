"""Converters from the meshes of other packages, duck-typed: neither meshio nor PyVista is
needed to import tessera."""

import numpy as np

from ._tessera import DataError, TetMesh

# VTK's cell type number of a linear tetrahedron.
_VTK_TETRA = 10


def _scalar_arrays(arrays):
    """The one-value-per-point entries of ``arrays`` (vectors and tensors left out), or
    ``None`` when there are none."""
    scalars = {key: np.asarray(value) for key, value in arrays.items()}
    scalars = {key: value for key, value in scalars.items() if value.ndim == 1}
    return scalars or None


def from_meshio(mesh, scalars=None, name="meshio mesh"):
    """A ``TetMesh`` from a ``meshio.Mesh``: its ``tetra`` cells, ``mesh.point_data`` as the
    per-point values (``scalars`` names the entry; default the first)."""
    blocks = [np.asarray(block.data) for block in mesh.cells if block.type == "tetra"]
    if not blocks:
        kinds = sorted({block.type for block in mesh.cells})
        raise DataError(
            f"{name}: no tetra cells (it has: {', '.join(kinds) or 'no cells'}); "
            "tetrahedralize it first, e.g. with TetGen"
        )
    tets = np.concatenate(blocks)
    point_data = _scalar_arrays(mesh.point_data)
    return TetMesh(mesh.points, tets, point_data=point_data, scalars=scalars, name=name)


def from_pyvista(grid, scalars=None, name="pyvista grid"):
    """A ``TetMesh`` from a ``pyvista.UnstructuredGrid``: its tetrahedra (other cells are
    left out), ``grid.point_data`` as the per-point values (``scalars`` names the array;
    default the active or first one)."""
    cells_dict = grid.cells_dict
    if _VTK_TETRA not in cells_dict:
        raise DataError(
            f"{name}: no tetrahedra (cell types {sorted(cells_dict)}); "
            "tetrahedralize it first, e.g. with grid.triangulate()"
        )
    point_data = _scalar_arrays({key: grid.point_data[key] for key in grid.point_data.keys()})
    if scalars is None:
        scalars = getattr(grid.point_data, "active_scalars_name", None)
    return TetMesh(
        np.asarray(grid.points),
        cells_dict[_VTK_TETRA],
        point_data=point_data or None,
        scalars=scalars if point_data else None,
        name=name,
    )
