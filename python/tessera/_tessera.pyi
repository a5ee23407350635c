"""Type stubs of the native module ``tessera._tessera`` (crates/tessera-py); the docstrings of
the classes and functions themselves say what each argument does."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "PathLike[str]"]
_Triple = Tuple[float, float, float]

class TesseraError(Exception): ...
class DataError(TesseraError): ...
class GpuError(TesseraError): ...

class Device:
    def __init__(
        self, index: Optional[int] = None, validation: bool = False, timeout: float = 60.0
    ) -> None: ...
    @property
    def name(self) -> str: ...
    def _capabilities_json(self) -> str: ...
    def memory(self) -> Dict[str, int]: ...
    def validation_errors(self) -> List[str]: ...

def devices() -> List[Tuple[int, str, str]]: ...

class Volume:
    def __init__(
        self,
        array: npt.ArrayLike,
        spacing: _Triple = (1.0, 1.0, 1.0),
        name: str = "array",
        nan_fill: Optional[float] = None,
    ) -> None: ...
    @property
    def shape(self) -> Tuple[int, int, int]: ...
    @property
    def spacing(self) -> _Triple: ...
    @property
    def dtype(self) -> str: ...
    @property
    def value_range(self) -> Tuple[float, float]: ...
    @property
    def name(self) -> str: ...
    def to_numpy(self) -> np.ndarray: ...

class TetMesh:
    def __init__(
        self,
        points: npt.ArrayLike,
        tets: npt.ArrayLike,
        point_data: Optional[Union[npt.ArrayLike, Dict[str, npt.ArrayLike]]] = None,
        cell_data: Optional[Union[npt.ArrayLike, Dict[str, npt.ArrayLike]]] = None,
        scalars: Optional[str] = None,
        name: str = "mesh",
    ) -> None: ...
    @property
    def n_points(self) -> int: ...
    @property
    def n_tets(self) -> int: ...
    @property
    def scalars(self) -> Optional[str]: ...

class GlyphField:
    def __init__(
        self,
        coeffs: npt.ArrayLike,
        basis: str = "descoteaux07",
        legacy: bool = True,
        spacing: Optional[_Triple] = None,
        z_slice: Optional[int] = None,
        glyph_radius: str = "minmax",
        name: str = "coefficients",
        affine: Optional[npt.ArrayLike] = None,
    ) -> None: ...
    @property
    def n_glyphs(self) -> int: ...

class Scene:
    def __init__(
        self, spec: str, basis: Optional[str] = None, glyph_radius: str = "minmax"
    ) -> None: ...
    @property
    def n_objects(self) -> int: ...

_Data = Union[Volume, TetMesh, GlyphField, Scene]

def load(
    spec: _Path,
    spacing: Optional[_Triple] = None,
    dims: Optional[Tuple[int, int, int]] = None,
    dtype: Optional[str] = None,
    endian: str = "little",
    header_bytes: int = 0,
    nan_fill: Optional[float] = None,
    basis: Optional[str] = None,
    glyph_radius: str = "minmax",
) -> _Data: ...

class Renderer:
    def __init__(
        self,
        device: Device,
        technique: Optional[str] = None,
        path: str = "auto",
        culling: Union[bool, str] = "auto",
        supersample: int = 1,
        msaa: int = 1,
        pre_split: Optional[int] = None,
        ambiguity: str = "decider",
        layout: str = "tet20",
        shadows: bool = False,
        light: Optional[_Triple] = None,
        light_dir: Optional[_Triple] = None,
        ao: Optional[int] = None,
        ao_radius: Optional[float] = None,
        gradient: bool = False,
        pmb_block: str = "8x8x4",
        hidden_side: str = "skip",
    ) -> None: ...
    def set_data(self, data: _Data) -> None: ...
    def render(
        self,
        camera: Optional[Sequence[float]] = None,
        size: Tuple[int, int] = (512, 512),
        iso: Optional[float] = None,
        iso_fraction: Optional[float] = None,
        tf: Optional[_Path] = None,
        integrate: Optional[str] = None,
        density: Optional[float] = None,
        background: Optional[str] = None,
        up: Optional[str] = None,
        dtype: Optional[Any] = None,
    ) -> np.ndarray:
        """(H, W, 4) uint8 colours, or with ``dtype="float32"`` the (H, W, 3) float quantity
        behind them (``quantity`` names it)."""
    @property
    def technique(self) -> Optional[str]: ...
    @property
    def quantity(self) -> Optional[str]: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def stats(self) -> Dict[str, Any]: ...

def marching_cubes(
    volume: Union[Volume, npt.ArrayLike],
    level: float,
    spacing: Optional[_Triple] = None,
    method: str = "meshlets",
    ambiguity: str = "decider",
    device: Optional[Device] = None,
    path: str = "auto",
) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(verts, faces, normals, values)`` in scikit-image's shapes and dtypes."""

def _bench(
    device: Device,
    scenario: str,
    quick: bool = False,
    frames: int = 100,
    warmup: int = 10,
    iso_fraction: float = 0.3,
    data: Optional[str] = None,
    sizes: Optional[List[Tuple[int, int]]] = None,
    keep_busy_ms: Optional[float] = None,
    techniques: Optional[List[str]] = None,
    paths: Optional[List[str]] = None,
    variants: Optional[str] = None,
    ablations: bool = False,
) -> Tuple[List[str], List[str]]: ...
