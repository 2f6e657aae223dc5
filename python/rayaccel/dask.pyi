# Type stubs of rayaccel.dask (python/tests/test_stubs.py checks them against the module).
import os
from typing import Any, Optional, Tuple, Union

import numpy as np
from numpy.typing import NDArray

import dask.array as da

from . import Accelerator, Scene

_Path = Union[str, os.PathLike[str]]
_Source = Union[_Path, Scene, Tuple[NDArray[Any], NDArray[Any]], "SceneSource"]
_Rays = Union[da.Array, NDArray[Any]]

class SceneSource:
    kind: str
    value: Any
    token: str
    def __init__(self, kind: str, value: Any, token: str) -> None: ...
    def scene(self) -> Scene: ...
    @classmethod
    def of(cls, source: _Source, check: bool = ...) -> "SceneSource": ...

class StructureFile:
    path: str
    spec: Optional[str]
    token: str
    def __init__(self, path: str, spec: Optional[str], token: str) -> None: ...
    @classmethod
    def of(cls, structure: Union[_Path, "StructureFile"], check: bool = ...) -> "StructureFile": ...

def intersect(scene_source: _Source, rays: _Rays, spec: str = ..., *,
              structure: Optional[Union[_Path, StructureFile]] = ..., check: bool = ..., packets: bool = ...,
              check_source: bool = ...) -> da.Array: ...
def occluded(scene_source: _Source, rays: _Rays, spec: str = ..., *,
             structure: Optional[Union[_Path, StructureFile]] = ..., check: bool = ...,
             check_source: bool = ...) -> da.Array: ...
def accelerator(source: SceneSource, spec: str, rays: int = ...,
                structure: Optional[StructureFile] = ...) -> Accelerator: ...
def cache_info() -> dict[str, Any]: ...
def clear_cache() -> None: ...
def set_cache_size(entries: int) -> int: ...
