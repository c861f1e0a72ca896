#!/usr/bin/env python3
"""The include check must fail on the fixture tree, with exactly these violations: an include that
runs back up (core -> io), another module's detail/ header, a public header and an example that
include a non-public header, and an include that does not exist. The fixture's allowed includes
(same module, a dependency, a transitive dependency, a program's own header) must not be reported.
usage: check_fixture.py CHECKER"""
import subprocess
import sys
from pathlib import Path

EXPECTED = {
    "src/core/value.cpp:2: module core may not include module io (\"beamtrace/io/reader.hpp\")",
    "src/top/job.cpp:3: module top may not include src/io/detail/buffer.hpp, a private detail/ header of module io",
    "src/top/job.cpp:4: cannot find \"io/missing.hpp\" (next to the file, or in include, src, bench/)",
    "include/beamtrace/io/reader.hpp:3: a public header may only include public headers, not src/io/detail/buffer.hpp (\"io/detail/buffer.hpp\")",
    "examples/example.cpp:2: an example (built against an installed copy) may only include public headers, not src/io/internal.hpp (\"io/internal.hpp\")",
}

fixture = Path(__file__).resolve().parent / "fixture"
run = subprocess.run([sys.executable, sys.argv[1], "--root", str(fixture)], capture_output=True, text=True)
got = set(run.stdout.splitlines())
ok = run.returncode == 1 and got == EXPECTED
if not ok:
    print(f"exit code {run.returncode} (expected 1)")
    for line in sorted(EXPECTED - got):
        print(f"missing:    {line}")
    for line in sorted(got - EXPECTED):
        print(f"unexpected: {line}")
    print(run.stderr, end="")
sys.exit(0 if ok else 1)
