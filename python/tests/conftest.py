"""Paths the tests need, from the environment ctest sets (python/CMakeLists.txt), else from the
repository layout (build/ and ../shared/data next to it)."""

import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def skip_unless_required(why):
    """Skips the test (a tool or data file is missing), or under BEAMTRACE_REQUIRE_ALL=1 (CI:
    every test must run, tests/test_support.hpp) fails it."""
    if os.environ.get("BEAMTRACE_REQUIRE_ALL") == "1":
        pytest.fail(f"expected to run but would skip (BEAMTRACE_REQUIRE_ALL=1): {why}")
    pytest.skip(why)


@pytest.fixture(scope="session")
def shared_data():
    path = pathlib.Path(os.environ.get("BEAMTRACE_SHARED_DATA_DIR", REPO.parent / "shared" / "data"))
    if not path.is_dir():
        skip_unless_required(f"no shared data at {path}")
    return path


@pytest.fixture(scope="session")
def cli():
    path = pathlib.Path(os.environ.get("BEAMTRACE_CLI", REPO / "build" / "beamtrace"))
    if not path.is_file():
        skip_unless_required(f"no beamtrace CLI at {path}")
    return path


@pytest.fixture(scope="session")
def examples():
    return pathlib.Path(os.environ.get("BEAMTRACE_EXAMPLES_DIR", REPO / "examples"))
