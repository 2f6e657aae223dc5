#!/usr/bin/env python3
"""Checks that the library's folders depend one way: a file under include/rayaccel/<layer>/ or src/<layer>/ may
include rayaccel headers of its own layer and of layers below it, never of a layer above it or beside it (two layers
of one rank know nothing of each other). Exits 1 listing every include that breaks the order (the CTest test
layers.one_way runs it over the source tree); also fails on a folder the order does not name, so a new layer must be
placed here first.

Usage: check_layers.py [repository root]   (default: the parent of this script's folder)
       check_layers.py --self-test          (the check itself: it must flag an upward and a sideways include)
"""
import pathlib
import re
import sys
import tempfile

# Lowest first; one rank may hold several layers that do not include each other.
LAYERS = [
    ["core"],      # vectors, boxes, rays, hits, primitives, statistics
    ["geometry"],  # the exact ray/primitive tests, one copy each
    ["scene"],     # Scene (what every structure is built over), built-in scenes, mesh import, ray files
    ["simd", "bv"],  # lane sets, Triangle4 blocks, the SIMD box and triangle kernels, CPU/ISA dispatch; bounding volumes
    ["accel"],     # the Accelerator interface and registry, and the spatial subdivisions
    ["bvh"],       # Bvh<BV> and its builders
    ["wide", "double"],  # the wide BVH (built from bvh's binary trees); the double-precision path (DoubleScene, its
                         # brute force and BVH over outward-rounded float boxes, make_double_accelerator)
    ["generalized"],  # beams and cones traced over the BVH family and the wide BVH
    ["compare", "render", "query", "instance"],  # Embree adapter; cameras, workloads, shading, images; inside tests,
    # signed distance; two-level structures over instanced scenes
    ["catalog"],   # the list of built-in structures: the one place that knows them all
    ["capi"],      # the C API (include/rayaccel/rayaccel_c.h): handles over scenes and structures made by spec
]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}
INCLUDE = re.compile(r'^\s*#\s*include\s+"rayaccel/([a-z_]+)/', re.MULTILINE)


def layer_files(root):
    for base in (root / "include" / "rayaccel", root / "src"):
        for path in sorted(base.rglob("*")):
            if path.suffix in (".h", ".hpp", ".cpp") and path.is_file():
                parts = path.relative_to(base).parts
                yield (parts[0] if len(parts) > 1 else None), path


def check(root):
    problems = []
    checked = 0
    for layer, path in layer_files(root):
        if layer is None:
            continue  # files directly under src/ or include/rayaccel/ (the C API's header) belong to no layer
        if layer not in RANK:
            problems.append(f"{path.relative_to(root)}: folder '{layer}' is not in the layer order (scripts/check_layers.py)")
            continue
        checked += 1
        for target in INCLUDE.findall(path.read_text(encoding="utf-8", errors="replace")):
            if target == layer:
                continue
            if target not in RANK:
                problems.append(f"{path.relative_to(root)}: includes rayaccel/{target}/, a folder not in the layer order")
            elif RANK[target] >= RANK[layer]:
                where = "above" if RANK[target] > RANK[layer] else "beside"
                problems.append(f"{path.relative_to(root)}: layer '{layer}' includes rayaccel/{target}/, {where} it")
    if checked == 0:
        problems.append(f"no library files found under {root}")
    return checked, problems


def self_test():
    """A tree that keeps the order passes; an upward include, a sideways one and an unknown folder are each caught."""
    cases = {
        "ok": ({"include/rayaccel/wide/a.h": '#include "rayaccel/simd/b.h"', "src/simd/b.cpp": '#include "rayaccel/core/c.h"'}, 0),
        "upward": ({"include/rayaccel/simd/a.h": '#include "rayaccel/wide/wide_bvh.h"'}, 1),
        "sideways": ({"src/bv/a.cpp": '  #  include "rayaccel/simd/lanes_sse.h"'}, 1),
        "unknown folder": ({"src/misc/a.cpp": '#include "rayaccel/core/vec3.h"', "src/core/b.cpp": ""}, 1),
    }
    failures = []
    for name, (files, expected) in cases.items():
        with tempfile.TemporaryDirectory() as tmp:
            for rel, text in files.items():
                path = pathlib.Path(tmp) / rel
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(text + "\n")
            _, problems = check(pathlib.Path(tmp))
            if len(problems) != expected:
                failures.append(f"self-test '{name}': expected {expected} problem(s), got {problems}")
    for f in failures:
        print(f)
    print("self-test: " + ("OK" if not failures else "FAILED"))
    return 1 if failures else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    checked, problems = check(root)
    for p in problems:
        print(p)
    order = " <- ".join("/".join(names) for names in LAYERS)
    print(f"{checked} files checked against the order {order}: " + ("OK" if not problems else f"{len(problems)} problems"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
