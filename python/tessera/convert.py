"""Converters from the meshes of other packages, duck-typed: neither meshio nor PyVista is
needed to import tessera.

Both take the mesh's point data when it has a one-value-per-point array, else its cell data
(one value per tet, averaged onto the points by ``TetMesh``): point values are drawn as they
are, while cell values are smoothed by the averaging. ``scalars`` names the array to take,
looked up in the point data first, then in the cell data."""

import numpy as np

from ._tessera import DataError, TetMesh

# VTK's cell type number of a linear tetrahedron.
_VTK_TETRA = 10


def _scalar_arrays(arrays):
    """The one-value-per-item entries of ``arrays`` (vectors and tensors left out; a column
    of shape (n, 1) counts as one value), or ``None`` when there are none."""
    scalars = {}
    for key, value in arrays.items():
        value = np.asarray(value)
        if value.ndim == 2 and value.shape[1] == 1:
            value = value[:, 0]
        if value.ndim == 1:
            scalars[key] = value
    return scalars or None


def _chosen(point_data, cell_data, scalars, name):
    """The keyword arguments of ``TetMesh`` for the scalars chosen (see the module)."""
    if scalars is not None:
        if point_data and scalars in point_data:
            return {"point_data": point_data, "scalars": scalars}
        if cell_data and scalars in cell_data:
            return {"cell_data": cell_data, "scalars": scalars}
        raise DataError(
            f"{name}: no one-value-per-point or per-cell array '{scalars}' "
            f"(point data: {', '.join(point_data or []) or 'none'}; "
            f"cell data: {', '.join(cell_data or []) or 'none'})"
        )
    if point_data:
        return {"point_data": point_data}
    if cell_data:
        return {"cell_data": cell_data}
    return {}


def from_meshio(mesh, scalars=None, name="meshio mesh"):
    """A ``TetMesh`` from a ``meshio.Mesh``: its ``tetra`` cells, with ``mesh.point_data``
    as the per-point values, or without any, ``mesh.cell_data`` (one array per cell block;
    the tetra blocks' values are taken) as per-tet values (``scalars`` names the entry;
    default the first)."""
    tetra = [i for i, block in enumerate(mesh.cells) if block.type == "tetra"]
    if not tetra:
        kinds = sorted({block.type for block in mesh.cells})
        raise DataError(
            f"{name}: no tetra cells (it has: {', '.join(kinds) or 'no cells'}); "
            "tetrahedralize it first, e.g. with TetGen"
        )
    tets = np.concatenate([np.asarray(mesh.cells[i].data) for i in tetra])
    cell_data = {}
    for key, blocks in (getattr(mesh, "cell_data", None) or {}).items():
        if len(blocks) != len(mesh.cells):
            raise DataError(
                f"{name}: cell_data['{key}'] has {len(blocks)} blocks for "
                f"{len(mesh.cells)} cell blocks"
            )
        cell_data[key] = np.concatenate([np.asarray(blocks[i]) for i in tetra])
    chosen = _chosen(
        _scalar_arrays(mesh.point_data), _scalar_arrays(cell_data), scalars, name
    )
    return TetMesh(mesh.points, tets, name=name, **chosen)


def from_pyvista(grid, scalars=None, name="pyvista grid"):
    """A ``TetMesh`` from a ``pyvista.UnstructuredGrid``: its tetrahedra (other cells are
    left out), with ``grid.point_data`` as the per-point values, or without any,
    ``grid.cell_data`` as per-tet values (``scalars`` names the array; default the active
    or first one)."""
    cells_dict = grid.cells_dict
    if _VTK_TETRA not in cells_dict:
        raise DataError(
            f"{name}: no tetrahedra (cell types {sorted(cells_dict)}); "
            "tetrahedralize it first, e.g. with grid.triangulate()"
        )
    point_data = _scalar_arrays({key: grid.point_data[key] for key in grid.point_data.keys()})
    # cells_dict keeps each type's cells in grid order, so the tets' values are the cell
    # arrays' entries where the type is a tetrahedron.
    is_tet = np.asarray(grid.celltypes) == _VTK_TETRA
    cell_data = _scalar_arrays(
        {key: np.asarray(grid.cell_data[key])[is_tet] for key in grid.cell_data.keys()}
    )
    if scalars is None:
        # The active array of the data that will be taken, where it holds one value per item.
        source, taken = (grid.point_data, point_data) if point_data else (grid.cell_data, cell_data)
        active = getattr(source, "active_scalars_name", None)
        if taken and active in taken:
            scalars = active
    chosen = _chosen(point_data, cell_data, scalars, name)
    return TetMesh(np.asarray(grid.points), cells_dict[_VTK_TETRA], name=name, **chosen)
