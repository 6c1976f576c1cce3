"""`pip install .`: builds vpcontact's Python module with the project's CMake and installs it.

The CMake build goes into build/pip/ of the source tree (kept between builds); it builds the
target vpcontact_python alone (-DBUILD_TESTING=OFF, no benchmarks, no PETSc engine: the module
runs the serial engine) for the interpreter that runs pip. With VPCONTACT_CMAKE_BUILD set to
a build directory where the module is built (build/ after `make build`), its package is
installed as it is, nothing is built (tests/python/pip_install.sh). The C++ dependencies are those of
scripts/install-deps.sh plus pybind11-dev. The installed module finds the built-in cases'
meshes in this source tree's cases/ and the Gmsh reader's module in build/pip/: keep them.
"""
import os
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = os.path.dirname(os.path.abspath(__file__))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("VPCONTACT_CMAKE_BUILD")
        if not build:
            build = os.path.join(SOURCE, "build", "pip")
            jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
            subprocess.check_call(["cmake", "-S", SOURCE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                                   "-DVPCONTACT_PYTHON=ON", "-DBUILD_TESTING=OFF", "-DVPCONTACT_BENCHMARKS=OFF",
                                   "-DVPCONTACT_ENABLE_PETSC=OFF", "-DPython_EXECUTABLE=" + sys.executable])
            subprocess.check_call(["cmake", "--build", build, "--target", "vpcontact_python", "-j", jobs])
        package = os.path.join(build, "python", "vpcontact")
        if not any(f.startswith("_core") for f in os.listdir(package)):
            raise RuntimeError("%s: no vpcontact._core: build the module first (make build)" % package)
        target = os.path.join(os.path.abspath(self.build_lib), "vpcontact")
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(package, target, ignore=shutil.ignore_patterns("__pycache__"))


setup(
    packages=[],
    ext_modules=[Extension("vpcontact._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    # setuptools' own files beside CMake's, not in build/ itself
    options={"build": {"build_base": os.path.join("build", "setuptools")},
             "egg_info": {"egg_base": os.path.join("build", "setuptools")}},
)
