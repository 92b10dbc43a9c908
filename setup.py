"""Builds the deepsea Python package with CMake (pyproject.toml; docs/python.md).

The extension deepsea._deepsea is CMake's target deepsea_python: setup.py configures a build
folder (or reuses one), builds that target and the OpenImageIO module, and copies both into
the package beside __init__.py, its stubs and py.typed. The extension's run path ($ORIGIN)
finds the OpenImageIO module there, so the installed package needs nothing from the build.

DEEPSEA_BUILD_DIR=<folder>: build in that CMake build folder (an existing one is reused, and
only what changed is rebuilt); default build/pip, configured Release without tests.
DEEPSEA_BUILD_JOBS=<n>: parallel build jobs (default: the cores).
"""

import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    return re.search(r"project\(deepsea VERSION ([0-9.]+)", text).group(1)


def cmake_cache(build, key):
    path = os.path.join(build, "CMakeCache.txt")
    if not os.path.exists(path):
        return None
    for line in open(path):
        if line.startswith(key + ":"):
            return line.split("=", 1)[1].strip()
    return None


class CMakeBuild(build_ext):
    """The extension and the OpenImageIO module from CMake, copied into the package."""

    def run(self):
        build = os.path.abspath(os.environ.get("DEEPSEA_BUILD_DIR") or
                                os.path.join(ROOT, "build", "pip"))
        if cmake_cache(build, "CMAKE_HOME_DIRECTORY") is None:
            subprocess.check_call([
                "cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                "-DDEEPSEA_BUILD_TESTS=OFF", "-DPython3_EXECUTABLE=" + sys.executable])
        jobs = os.environ.get("DEEPSEA_BUILD_JOBS") or str(os.cpu_count() or 1)
        subprocess.check_call(["cmake", "--build", build, "--target", "deepsea_python",
                               "deepsea_oiio", "-j", jobs])
        package = cmake_cache(build, "DEEPSEA_PYTHON_PACKAGE_DIR")
        if package is None:
            sys.exit(f"deepsea: {build} builds no Python module (no pybind11-dev or "
                     "python3-dev when it was configured)")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = [f for f in os.listdir(package) if f.startswith("_deepsea.") and f.endswith(".so")]
        if "_deepsea" + suffix not in built:
            sys.exit(f"deepsea: {build} holds {', '.join(built) or 'no extension'}, not "
                     f"_deepsea{suffix} for {sys.executable}: give another DEEPSEA_BUILD_DIR "
                     "or none")
        for ext in self.extensions:
            target = self.get_ext_fullpath(ext.name)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            shutil.copyfile(os.path.join(package, "_deepsea" + suffix), target)
            plugin = os.path.join(build, "lib", "deepsea", "libdeepsea_oiio.so")
            shutil.copyfile(plugin, os.path.join(os.path.dirname(target), "libdeepsea_oiio.so"))


setup(
    version=version(),
    packages=["deepsea"],
    package_dir={"deepsea": "python/deepsea"},
    package_data={"deepsea": ["_deepsea.pyi", "py.typed"]},
    ext_modules=[Extension("deepsea._deepsea", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    # setuptools' own folders inside the CMake build's, not beside it.
    options={"build": {"build_base": os.path.join("build", "setuptools")}},
)
