# SPDX-License-Identifier: BSD-3-Clause
"""The build of the Python package: CMake configures the project and builds the extension
`_sparsempm` (python/CMakeLists.txt), which setuptools puts beside sparsempm/__init__.py.

Extra CMake arguments come from SPARSEMPM_CMAKE_ARGS (space-separated), the number of build
jobs from SPARSEMPM_BUILD_JOBS (default 2), the CMake build directory from SPARSEMPM_BUILD_DIR
(default: under setuptools' build directory). A build directory beside an earlier build of the
same flags (`build` and `build.pip`), with CCACHE_BASEDIR set to the source tree for both, has
every object served by ccache.
"""

import os
import pathlib
import re
import shlex
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = pathlib.Path(__file__).resolve().parent
# One version: CMakeLists.txt's project(sparsempm VERSION ...).
VERSION = re.search(r"project\(sparsempm VERSION ([0-9.]+)",
                    (SOURCE / "CMakeLists.txt").read_text()).group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(os.environ.get("SPARSEMPM_BUILD_DIR", "")
                             or pathlib.Path(self.build_temp) / "cmake").resolve()
        build.mkdir(parents=True, exist_ok=True)
        args = [f"-DPython_EXECUTABLE={sys.executable}", "-DCMAKE_BUILD_TYPE=Release",
                "-DSMPM_BUILD_TESTS=OFF", "-DSMPM_BUILD_BENCHMARKS=OFF",
                "-DSMPM_BUILD_EXAMPLES=OFF",
                *shlex.split(os.environ.get("SPARSEMPM_CMAKE_ARGS", ""))]
        subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build), *args], check=True)
        jobs = os.environ.get("SPARSEMPM_BUILD_JOBS", "2")
        subprocess.run(["cmake", "--build", str(build), "--target", "_sparsempm", "-j", jobs],
                       check=True)
        built = next((build / "python" / "sparsempm").glob("_sparsempm*.so"))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built), str(target))


setup(version=VERSION, ext_modules=[CMakeExtension("sparsempm._sparsempm")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/python-package"}})
