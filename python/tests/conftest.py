"""Shared fixtures of the Python tests: small scenes, random rays, and the CLI (RAYACCEL_CLI, set by CTest)."""
import os
import shutil

import numpy as np
import pytest

import rayaccel


@pytest.fixture(scope="session")
def cli():
    """Path of the rayaccel CLI; the test is skipped when neither RAYACCEL_CLI nor PATH has one."""
    path = os.environ.get("RAYACCEL_CLI") or shutil.which("rayaccel")
    if not path or not os.path.exists(path):
        pytest.skip("no rayaccel CLI (CTest sets RAYACCEL_CLI)")
    return path


def random_rays(scene, count, seed=0):
    """(count, 8) float32 rays from points around the scene box toward points inside it, some with finite t_max."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    center, extent = (lo + hi) / 2, (hi - lo)
    origins = center + (rng.random((count, 3)) - 0.5) * extent * 3
    targets = center + (rng.random((count, 3)) - 0.5) * extent
    rays = np.zeros((count, 8), dtype=np.float32)
    rays[:, 0:3] = origins
    rays[:, 4:7] = targets - origins
    rays[:, 7] = np.where(rng.random(count) < 0.2, 0.8, np.inf)
    rays[:, 3] = np.where(rng.random(count) < 0.1, 0.3, 0.0)
    return rays


@pytest.fixture(scope="session")
def soup():
    """300 random triangles in [-1, 1]^3 from numpy arrays (shared vertices, so edges are shared too)."""
    rng = np.random.default_rng(7)
    vertices = rng.uniform(-1, 1, size=(400, 3)).astype(np.float32)
    triangles = rng.integers(0, len(vertices), size=(300, 3)).astype(np.uint32)
    return rayaccel.mesh(vertices, triangles, name="soup")
