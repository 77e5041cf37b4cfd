"""Builds the extension robcal._robcal with CMake (the project's own build) for setuptools.

`pip install --no-build-isolation .` runs this. The extension and the robot library data
(data/robots) go into the package, so the installed package needs neither the source tree nor the
build tree. Environment:
  ROBCAL_CMAKE_BUILD_DIR  a configured CMake build tree to build `_robcal` in (default:
                          build/python-package, configured here without tests and benches)
  ROBCAL_BUILD_JOBS       parallel build jobs (default: the CPU count)
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent


def project_version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    return re.search(r"project\(robcal VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = Path(os.environ.get("ROBCAL_CMAKE_BUILD_DIR") or SOURCE / "build" / "python-package")
        if not (build_dir / "CMakeCache.txt").exists():
            configure = ["cmake", "-S", str(SOURCE), "-B", str(build_dir),
                         "-DCMAKE_BUILD_TYPE=Release", "-DROBCAL_BUILD_TESTS=OFF",
                         "-DROBCAL_BUILD_BENCH=OFF", f"-DPython3_EXECUTABLE={sys.executable}"]
            if shutil.which("ccache"):
                configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
            subprocess.run(configure, check=True)
        jobs = os.environ.get("ROBCAL_BUILD_JOBS") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_robcal", "-j", jobs],
                       check=True)
        built = sorted((build_dir / "python" / "robcal").glob("_robcal*.so"))
        if not built:
            raise RuntimeError(f"CMake built no _robcal*.so in {build_dir}/python/robcal")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)
        # The robot library, found by the package through ROBCAL_DATA_DIR (see __init__.py).
        shutil.copytree(SOURCE / "data" / "robots", target.parent / "data" / "robots",
                        dirs_exist_ok=True)


# setuptools' intermediate files stay out of the source tree's python/ and out of CMake's build/.
STAGING = SOURCE / "build" / "setuptools"
STAGING.mkdir(parents=True, exist_ok=True)

setup(
    version=project_version(),
    ext_modules=[Extension("robcal._robcal", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(STAGING)}, "egg_info": {"egg_base": str(STAGING)}},
)
