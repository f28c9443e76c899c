"""Point-cloud files through PCL's reader/writer (built from cpp/io/pcl_io_module.cpp)."""

import numpy
import numpy.typing

PCL_VERSION: str

class FileMissingError(FileNotFoundError): ...
class WriteFailedError(OSError): ...

def load_pcd(path: str) -> tuple[numpy.typing.NDArray[numpy.float32], int, int]:
    """Read a PCD file -> (points (N, 3) float32, width, height); NaN rows kept.

    DATA ascii bodies are checked line by line first: ValueError naming the line number and
    the field for a value that is not a number of the field's TYPE ('nan'/'inf' are
    numbers), a line with too few/many values, or fewer/more data lines than POINTS."""

def save_pcd(path: str, points: numpy.typing.ArrayLike, width: int | None = None,
             height: int | None = None, encoding: str = "binary_compressed") -> None:
    """Write (N, 3) points (fields x y z, float32); encoding: binary_compressed|binary|ascii."""

def load_ply(path: str) -> numpy.typing.NDArray[numpy.float32]:
    """Read the vertices' x/y/z of a PLY file -> (N, 3) float32.

    ASCII bodies are checked line by line first (one element per line, exactly its
    properties' values, as many lines as the header declares): ValueError naming the line
    number, the element and the property otherwise."""
