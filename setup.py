"""`pip install .`: CMake builds only the extension `_beamtrace` (and the libraries it links),
setuptools installs it with the package `python/beamtrace` (docs/python.md, "Install with pip").

Offline, from Debian packages: `pip install --no-build-isolation --no-index .` in a venv made
with `--system-site-packages` (NumPy, setuptools and wheel from Debian). Environment:
- BEAMTRACE_CMAKE_BUILD_DIR: the CMake build folder (default: build-pip/ in the repository, kept
  between installs so a reinstall only rebuilds what changed). An already configured folder, such
  as the build/ of the README, is built as it is (its Python must be this one's version).
- BEAMTRACE_CMAKE_ARGS: more arguments for the first configure (split as a shell would).
- CMAKE_BUILD_PARALLEL_LEVEL: compile jobs (default: every core).
ccache, where it is on PATH, compiles through it (as scripts/test.sh does).
"""

import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(beamtrace VERSION ([0-9.]+)", text).group(1)


def configure(build_dir):
    args = [
        "cmake", "-S", str(ROOT), "-B", str(build_dir),
        "-DCMAKE_BUILD_TYPE=Release",
        "-DBEAMTRACE_PYTHON=ON",
        "-DBEAMTRACE_BUILD_TESTS=OFF",
        "-DBEAMTRACE_BUILD_BENCH=OFF",
        f"-DPython3_EXECUTABLE={sys.executable}",
    ]
    if shutil.which("ccache"):
        args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    args += shlex.split(os.environ.get("BEAMTRACE_CMAKE_ARGS", ""))
    subprocess.run(args, check=True)


def cmake_build_dir():
    return pathlib.Path(os.environ.get("BEAMTRACE_CMAKE_BUILD_DIR") or ROOT / "build-pip")


class CMakeBuild(build_ext):
    """Builds each extension with CMake's target of the same name and copies the module that
    python/CMakeLists.txt puts in BUILD/python/beamtrace/ to where setuptools packs it."""

    def build_extension(self, ext):
        build_dir = cmake_build_dir()
        if not (build_dir / "CMakeCache.txt").is_file():
            configure(build_dir)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        target = ext.name.rpartition(".")[2]
        subprocess.run(["cmake", "--build", str(build_dir), "--target", target, "-j", jobs],
                       check=True)
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = build_dir / "python" / "beamtrace" / (target + suffix)
        if not built.is_file():
            found = sorted(p.name for p in built.parent.glob(target + ".*"))
            raise RuntimeError(
                f"{built}: not built (found: {', '.join(found) or 'nothing'}); the CMake build in "
                f"{build_dir} must be configured for this Python ({sys.executable}, pybind11, "
                "NumPy); see docs/python.md")
        dest = pathlib.Path(self.get_ext_fullpath(ext.name))
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, dest)


setup(
    version=project_version(),
    packages=["beamtrace"],
    package_dir={"": "python"},
    ext_modules=[Extension("beamtrace._beamtrace", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' own scratch folder, in the CMake build folder (not in the README's build/).
    options={"build": {"build_base": str(cmake_build_dir() / "setuptools")}},
)
