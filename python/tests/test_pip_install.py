"""`pip install .` (setup.py, pyproject.toml; docs/python.md, "Install with pip"): offline, into
a venv that sees Debian's NumPy, setuptools and wheel; the installed package imports from the venv
(not from build/python) and traces."""

import importlib.util
import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

from conftest import REPO, skip_unless_required

# A ray straight down onto a triangle 5 m below: the installed module must trace it.
CHECK = """
import pathlib, sys
import beamtrace
from beamtrace import _beamtrace
scene = beamtrace.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
hits = scene.trace([[0.25, 0.25, 5.0]], [[0.0, 0.0, -1.0]])
print(beamtrace.__version__, pathlib.Path(beamtrace.__file__).parent, \
      pathlib.Path(_beamtrace.__file__).parent, hits.range_m[0], hits.face[0])
"""


def project_version():
    text = (REPO / "CMakeLists.txt").read_text()
    return re.search(r"project\(beamtrace VERSION ([0-9.]+)", text).group(1)


@pytest.fixture
def venv(tmp_path):
    for module in ("venv", "setuptools", "wheel", "pip"):
        if importlib.util.find_spec(module) is None:
            skip_unless_required(f"no {module} for {sys.executable} (scripts/install-deps.sh)")
    path = tmp_path / "venv"
    # Without its own pip: the venv runs Debian's (system site packages), which saves seconds.
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", "--system-site-packages",
                    str(path)], check=True)
    return path / "bin" / "python"


def pip_install(python, cmake_build_dir, tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["BEAMTRACE_CMAKE_BUILD_DIR"] = str(cmake_build_dir)
    env["PIP_CACHE_DIR"] = str(tmp_path / "pip-cache")
    run = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation",
                          "--no-index", "--no-cache-dir", "--disable-pip-version-check", "."],
                         cwd=REPO, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    # Imported from elsewhere, without PYTHONPATH: only the venv's site-packages can answer.
    check = subprocess.run([str(python), "-c", CHECK], cwd=tmp_path, env=env,
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    version, package, module, range_m, face = check.stdout.split()
    site = python.parent.parent / "lib"
    assert pathlib.Path(package).is_relative_to(site), package
    assert pathlib.Path(module) == pathlib.Path(package)
    assert version == project_version()
    assert float(range_m) == pytest.approx(5.0, abs=1e-5) and int(face) == 0


def test_pip_install_from_the_configured_build_tree(venv, tmp_path):
    """The quick way: setup.py builds the target _beamtrace in the build tree of this test run
    (already built: nothing to compile) and installs it."""
    build = pathlib.Path(os.environ.get("BEAMTRACE_BUILD_DIR", REPO / "build"))
    if not (build / "CMakeCache.txt").is_file():
        skip_unless_required(f"no configured CMake build at {build}")
    shutil.rmtree(build / "setuptools", ignore_errors=True)  # setup.py's scratch: no stale copy
    pip_install(venv, build, tmp_path)


def test_pip_install_configures_and_builds_its_own_tree(venv, tmp_path):
    """What `pip install .` does by default: configure a CMake build of its own and build only
    _beamtrace. About 10 s on 2 cores with ccache warm from the build of this test run (a folder
    next to build/, so that ccache's relative paths match); minutes without ccache: skipped then."""
    if shutil.which("ccache") is None and os.environ.get("BEAMTRACE_PIP_FULL_BUILD") != "1":
        pytest.skip("no ccache: a full build would take minutes (BEAMTRACE_PIP_FULL_BUILD=1 runs it)")
    build = REPO / "build-pytest-pip"
    shutil.rmtree(build, ignore_errors=True)
    try:
        pip_install(venv, build, tmp_path)
        assert (build / "CMakeCache.txt").is_file()
        assert not (build / "beamtrace").exists()  # only the module's target was built
    finally:
        shutil.rmtree(build, ignore_errors=True)
