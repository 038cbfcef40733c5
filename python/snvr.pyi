"""libsnvr: a thin, closed, printable shell around a point cloud (Allen-Cahn narrow volume, Li et al. 2014)."""
import os
from typing import Any, Callable, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

class Cancelled(RuntimeError):
    """The progress callback returned False: the run stopped and freed what it held."""

class Shell:
    """The shell and everything the run reports."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> npt.NDArray[np.uint32]: ...
    @property
    def outlier_mask(self) -> npt.NDArray[np.bool_]: ...
    @property
    def outliers(self) -> npt.NDArray[np.float64]: ...
    @property
    def shift(self) -> Tuple[float, float, float]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def report(self) -> dict[str, Any]: ...
    def write(self, path: str) -> None: ...
    def to_open3d(self) -> Any: ...
    def to_trimesh(self) -> Any: ...
    def to_pyvista(self) -> Any: ...

def shell(
    points: Union[npt.ArrayLike, str, os.PathLike],
    *,
    resolution: Optional[int] = None,
    voxel: Optional[float] = None,
    offset: Optional[float] = None,
    thickness: Optional[float] = None,
    offset_cells: Optional[float] = None,
    keep_outliers: bool = False,
    origin: str = "auto",
    fairing: int = 2,
    min_piece_volume: float = 0.0,
    keep_largest: int = 0,
    measure: bool = False,
    smoothing: Optional[float] = None,
    dt_cells: Optional[float] = None,
    steps: Optional[int] = None,
    tube_inner: Optional[float] = None,
    tube_outer: Optional[float] = None,
    free_flow: bool = False,
    eps_cells: Optional[float] = None,
    xi_cells: Optional[float] = None,
    tol: Optional[float] = None,
    max_cycles: Optional[int] = None,
    tile_cells: int = 0,
    tile_halo_cells: Optional[int] = None,
    max_memory: Optional[int] = None,
    temp_dir: str = "",
    precision: str = "float",
    device: str = "auto",
    written_as: str = ".stl",
    keep_field: bool = False,
    units: str = "mm",
    scale: float = 1.0,
    progress: Optional[Callable[[str, int, int], Optional[bool]]] = None,
) -> Shell: ...

def read_points(path: str) -> npt.NDArray[np.float32] | npt.NDArray[np.float64]: ...
