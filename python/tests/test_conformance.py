"""Every spec `rayaccel list --names` prints, built from Python, agrees with brute force on a small scene: the same
hit or miss, bit-identical t, u, v on the same primitive (one triangle kernel), a tie in t otherwise, and the same
occlusion answers."""
import numpy as np
import pytest

import rayaccel
from conftest import random_rays

SPECS = rayaccel.specs()


def test_structures_list_every_spec():
    listed = [v for s in rayaccel.structures() for v in s["variants"]]
    assert listed == SPECS and "bvh_wide" in SPECS and SPECS[0] == "brute_force"
    for s in rayaccel.structures():
        assert s["description"] and all({"key", "type", "default", "description", "choices"} <= set(o)
                                        for o in s["options"])


@pytest.fixture(scope="module")
def oracle(soup):
    rays = np.concatenate([random_rays(soup, 1500, seed=1), rayaccel.Camera.framing(soup).rays(24, 24).reshape(-1, 8)])
    brute = rayaccel.build(soup, "brute_force")
    return rays, brute.intersect(rays), brute.occluded(rays)


@pytest.mark.parametrize("spec", SPECS)
def test_agrees_with_brute_force(spec, soup, oracle):
    rays, expected, expected_occluded = oracle
    accel = rayaccel.build(soup, spec)
    assert accel.spec == spec and accel.validate() == []
    hits = accel.intersect(rays)
    np.testing.assert_array_equal(hits.hit, expected.hit)
    same = hits.prim_id == expected.prim_id
    for field in ("t", "u", "v"):
        np.testing.assert_array_equal(getattr(hits, field)[same], getattr(expected, field)[same])
    np.testing.assert_allclose(hits.t[~same], expected.t[~same], rtol=1e-6)
    np.testing.assert_array_equal(accel.occluded(rays), expected_occluded)


def test_spheres_agree_with_brute_force():
    scene = rayaccel.builtin("sphereflake", level=2)
    rays = random_rays(scene, 2000, seed=4)
    a = rayaccel.build(scene, "bvh_wide").intersect(rays)
    b = rayaccel.build(scene, "brute_force").intersect(rays)
    assert a.tobytes() == b.tobytes()
