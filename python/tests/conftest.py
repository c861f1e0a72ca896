"""Paths the tests need, from the environment ctest sets (python/CMakeLists.txt), else from the
repository layout (build/ and ../shared/data next to it)."""

import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def shared_data():
    path = pathlib.Path(os.environ.get("BEAMTRACE_SHARED_DATA_DIR", REPO.parent / "shared" / "data"))
    if not path.is_dir():
        pytest.skip(f"no shared data at {path}")
    return path


@pytest.fixture(scope="session")
def cli():
    path = pathlib.Path(os.environ.get("BEAMTRACE_CLI", REPO / "build" / "beamtrace"))
    if not path.is_file():
        pytest.skip(f"no beamtrace CLI at {path}")
    return path


@pytest.fixture(scope="session")
def examples():
    return pathlib.Path(os.environ.get("BEAMTRACE_EXAMPLES_DIR", REPO / "examples"))
