"""The type stubs (rayaccel/__init__.pyi, dask.pyi) against the running package: every public name, class member and
parameter appears in both; py.typed ships beside them; `cmake --install` puts the package, stubs included, under
RAYACCEL_INSTALL_PYTHONDIR, where the interpreter finds it (issue #37)."""
import ast
import inspect
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest

import rayaccel

SOURCE = Path(__file__).resolve().parents[1] / "rayaccel"


def stub(name):
    """{public name: ast node} of a stub file's top level; a class's node gets .members, {name: [nodes]}."""
    out = {}
    for node in ast.parse((SOURCE / name).read_text()).body:
        names = [t.id for t in getattr(node, "targets", [])] or [getattr(node, "name", None)] or []
        if isinstance(node, ast.AnnAssign):
            names = [node.target.id]
        for n in names:
            if n and (not n.startswith("_") or n.startswith("__")):
                out[n] = node
        if isinstance(node, ast.ClassDef):
            node.members = {}
            for member in node.body:
                key = member.target.id if isinstance(member, ast.AnnAssign) else getattr(member, "name", None)
                if key:
                    node.members.setdefault(key, []).append(member)
    return out


def stub_parameters(function, in_class):
    a = function.args
    positional = a.posonlyargs + a.args
    defaults = [False] * (len(positional) - len(a.defaults)) + [True] * len(a.defaults)
    out = [(p.arg, "positional", d) for p, d in zip(positional, defaults)]
    out += [(p.arg, "keyword", d is not None) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.vararg:
        out.append((a.vararg.arg, "*", False))
    if a.kwarg:
        out.append((a.kwarg.arg, "**", False))
    return out[1:] if in_class else out  # self or cls


def split_top_level(text):
    parts, depth, current = [], 0, ""
    for ch in text:
        depth += ch in "[(" and 1 or (ch in "])" and -1 or 0)
        if ch == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += ch
    return parts + ([current] if current.strip() else [])


def runtime_parameters(obj, in_class):
    """(name, kind, has default) of a Python function, or names parsed from a pybind11 docstring's signature (kind
    and default None); without self where obj is a method taken from its class."""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        line = obj.__doc__.strip().splitlines()[0]
        inner = line[line.index("(") + 1:line.rindex(") ->")]
        params = [p.split(":")[0].strip() for p in split_top_level(inner)]
        return [(p, None, None) for p in (params[1:] if in_class else params)]
    kinds = {inspect.Parameter.POSITIONAL_ONLY: "positional", inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
             inspect.Parameter.KEYWORD_ONLY: "keyword", inspect.Parameter.VAR_POSITIONAL: "*",
             inspect.Parameter.VAR_KEYWORD: "**"}
    out = [(p.name, kinds[p.kind], p.default is not inspect.Parameter.empty) for p in signature.parameters.values()]
    return out[1:] if in_class and inspect.isfunction(obj) else out  # a classmethod comes bound, without cls


def same_parameters(stub_params, runtime_params, where):
    if runtime_params and runtime_params[0][2] is None:  # pybind11: names only
        assert [p[0] for p in stub_params] == [p[0] for p in runtime_params], where
    else:
        assert stub_params == runtime_params, where


def check_class(cls, node, instance_attributes):
    runtime = {n for n in dir(cls) if not n.startswith("_")}
    stubbed = {n for n in node.members if not n.startswith("_")}
    assert runtime <= stubbed, f"{cls.__name__}: missing from the stub: {sorted(runtime - stubbed)}"
    for name in stubbed - runtime:  # data attributes set on instances
        assert all(isinstance(m, ast.AnnAssign) for m in node.members[name]), f"{cls.__name__}.{name}"
        assert name in instance_attributes.get(cls.__name__, ()), f"{cls.__name__}.{name} is not on an instance"
    for name, members in node.members.items():
        if name.startswith("_") and name != "__init__" or isinstance(members[0], ast.AnnAssign):
            continue
        value = inspect.getattr_static(cls, name, None)
        decorators = [getattr(d, "id", None) for d in members[0].decorator_list]
        if "property" in decorators:
            assert isinstance(value, property), f"{cls.__name__}.{name} is a property in the stub only"
            continue
        function = getattr(cls, name)
        if name == "__init__" and not inspect.isfunction(function):
            continue  # a pybind11 constructor: checked through the Python subclass where there is one
        same_parameters(stub_parameters(members[0], True), runtime_parameters(function, True),
                        f"{cls.__name__}.{name}")


def check_module(module, stubs, instance_attributes):
    for name, node in stubs.items():
        assert hasattr(module, name), f"{module.__name__}.{name} is in the stub only"
        value = getattr(module, name)
        if isinstance(node, ast.ClassDef):
            check_class(value, node, instance_attributes)
        elif isinstance(node, ast.FunctionDef):
            same_parameters(stub_parameters(node, False), runtime_parameters(value, False), f"{module.__name__}.{name}")


def test_package_stubs_match_the_package():
    stubs = stub("__init__.pyi")
    assert set(rayaccel.__all__) == set(stubs), set(rayaccel.__all__) ^ set(stubs)
    hits = rayaccel.build(rayaccel.builtin("sphere")).intersect([0, 0, 5], [0, 0, -1], stats=True)
    loaded = rayaccel.load("builtin:sphere")
    instance_attributes = {"Hits": vars(hits), "TraversalStats": vars(hits.stats), "Scene": vars(loaded)}
    check_module(rayaccel, stubs, instance_attributes)


def test_dask_stubs_match_the_module():
    rd = pytest.importorskip("rayaccel.dask", reason="dask is not installed")
    stubs = stub("dask.pyi")
    assert set(rd.__all__) <= set(stubs)
    check_module(rd, stubs, {})


def test_stub_check_can_fail():
    """The check finds a parameter renamed (in a Python method and in a compiled one) and a method missing."""
    stubs = stub("__init__.pyi")
    node = stubs["Accelerator"]
    node.members["intersect"][0].args.args[1].arg = "origins"
    with pytest.raises(AssertionError, match="Accelerator.intersect"):
        check_class(rayaccel.Accelerator, node, {})
    del node.members["closest_points"]
    with pytest.raises(AssertionError, match="closest_points"):
        check_class(rayaccel.Accelerator, node, {})
    node = stubs["InstancedScene"]  # a pybind11 method: names read from its docstring
    node.members["set_transform"][0].args.args[2].arg = "matrix"
    with pytest.raises(AssertionError, match="InstancedScene.set_transform"):
        check_class(rayaccel.InstancedScene, node, {})


def test_stubs_and_marker_ship_with_the_package():
    package = Path(rayaccel.__file__).parent
    for name in ("py.typed", "__init__.pyi", "dask.pyi"):
        assert (package / name).is_file(), f"{name} is not beside {rayaccel.__file__}"


@pytest.mark.skipif(not os.environ.get("RAYACCEL_BUILD_DIR") or not os.environ.get("RAYACCEL_INSTALL_PYTHONDIR"),
                    reason="needs RAYACCEL_BUILD_DIR and RAYACCEL_INSTALL_PYTHONDIR (set by CTest)")
def test_cmake_install_installs_the_package(tmp_path):
    cmake = os.environ.get("RAYACCEL_CMAKE", "cmake")
    subprocess.run([cmake, "--install", os.environ["RAYACCEL_BUILD_DIR"], "--component", "python", "--prefix",
                    str(tmp_path)], check=True, capture_output=True)
    pythondir = os.environ["RAYACCEL_INSTALL_PYTHONDIR"]
    site = Path(pythondir) if os.path.isabs(pythondir) else tmp_path / pythondir
    installed = site / "rayaccel"
    for name in ("__init__.py", "_rays.py", "dask.py", "__init__.pyi", "dask.pyi", "py.typed"):
        assert (installed / name).is_file(), name
    assert list(installed.glob("_core*.so"))
    run = subprocess.run([sys.executable, "-c", "import rayaccel; print(rayaccel.__file__); "
                          "print(rayaccel.build(rayaccel.builtin('sphere')).intersect([0, 0, 5], [0, 0, -1]).t)"],
                         env=dict(os.environ, PYTHONPATH=str(site)), cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    where, t = run.stdout.splitlines()
    assert where.startswith(str(installed)) and np.isfinite(float(t.strip("[]")))
    # The default is where this interpreter looks under the prefixes /usr/local (Debian) or a venv's own.
    site_dir = "dist-packages" if "deb_system" in sysconfig.get_scheme_names() else "site-packages"
    default = f"lib/python{sys.version_info[0]}.{sys.version_info[1]}/{site_dir}"
    if pythondir == default and site_dir == "dist-packages":
        assert os.path.join("/usr/local", default) in sys.path
