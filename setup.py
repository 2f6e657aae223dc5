"""`pip install .`: the rayaccel Python package (python/rayaccel) with its compiled core built by CMake, so the
module gets exactly the library's flags. Offline, with Debian's packages (scripts/setup.sh installs them):

    /usr/bin/python3 -m pip install . --no-build-isolation --no-deps --break-system-packages

CMake's build tree is build-python/ (kept, so a second install only recompiles what changed);
CMAKE_BUILD_PARALLEL_LEVEL sets the compile jobs.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(rayaccel VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    """Configures the project with only the Python module enabled and builds its target."""

    def build_extension(self, ext):
        build_dir = Path(self.build_temp).resolve() / "cmake"
        configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                     "-DRAYACCEL_BUILD_TESTS=OFF", "-DRAYACCEL_BUILD_BENCH=OFF", "-DRAYACCEL_BUILD_PYTHON=ON",
                     f"-DRAYACCEL_PYTHON_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja") and not (build_dir / "CMakeCache.txt").exists():
            configure += ["-G", "Ninja"]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "rayaccel_python", "-j", jobs], check=True)
        built = sorted((build_dir / "python" / "rayaccel").glob("_core*.so"))
        if not built:
            raise RuntimeError("CMake did not build the Python module: is pybind11 installed (Debian pybind11-dev, "
                               "python3-dev; run scripts/setup.sh)? See the CMake output above.")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    name="rayaccel",
    version=project_version(),
    description="Exact ray queries over triangle meshes and spheres with every classic acceleration structure",
    packages=["rayaccel"],
    package_dir={"": "python"},
    package_data={"rayaccel": ["py.typed", "*.pyi"]},  # PEP 561: the type stubs ship with the package
    ext_modules=[Extension("rayaccel._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    python_requires=">=3.9",
    install_requires=["numpy"],
    extras_require={"plot": ["matplotlib"]},
    options={"build": {"build_base": "build-python"}},
    zip_safe=False,
)
