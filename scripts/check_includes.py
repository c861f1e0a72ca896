#!/usr/bin/env python3
"""Checks every #include "..." of src/, include/, apps/, bench/, examples/ and fuzz/ against the
module graph declared in cmake/modules.txt (the file CMake makes its library targets from).

Each file belongs to a module: include/beamtrace/<m>/ and src/<m>/ to library module <m>,
bench/harness/ to `harness`, bench/ to `bench`, apps/, examples/ and fuzz/ to `apps`, `examples`
and `fuzz`. An include is resolved as the compiler does (next to the including file, then
include/, src/, bench/) and is a violation when
  - its module is not the including file's module nor reachable from it in the graph (an include
    that runs back up, or sideways to a module not declared as a dependency);
  - it is another module's private header (src/<m>/detail/);
  - a public header (include/) or an example (built against an installed copy) includes a header
    that is not public (not installed);
  - it cannot be found, or its file lies in a module that modules.txt does not declare.
Prints one line per violation, `file:line: why`, and exits 1 if there is any.

usage: check_includes.py [--root DIR] [--modules FILE]   (defaults: the repository, DIR/cmake/modules.txt)
"""
import argparse
import re
import sys
from pathlib import Path

SCANNED = ("src", "include", "apps", "bench", "examples", "fuzz")
EXTENSIONS = {".hpp", ".cpp", ".h", ".inl"}
SEARCH_PATH = ("include", "src", "bench")  # the -I folders of the build, in order
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def read_graph(path):
    """The [library] and [programs] lines of modules.txt: {module: [direct dependencies]}, the
    library modules in declaration order, and every problem with the graph itself."""
    deps, library, problems = {}, [], []
    section = None
    for number, raw in enumerate(path.read_text().splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        header = re.fullmatch(r"\[([a-z]+)\]", line)
        if header:
            section = header.group(1)
            continue
        entry = re.fullmatch(r"([a-z_]+):\s*(.*)", line)
        if not entry or section not in ("library", "programs"):
            problems.append(f"{path}:{number}: expected `module: dependencies` in [library] or [programs]")
            continue
        module, names = entry.group(1), entry.group(2).split()
        for name in names:
            if name not in deps:  # only earlier lines: the graph cannot have a cycle
                problems.append(f"{path}:{number}: {module} uses {name}, which is not declared above it")
        deps[module] = names
        if section == "library":
            library.append(module)
    return deps, library, problems


def reachable(deps):
    """For each module, the modules it may include: itself and its dependencies, transitively."""
    closure = {}
    for module, names in deps.items():  # declaration order: dependencies come first
        allowed = {module}
        for name in names:
            allowed |= closure.get(name, set())
        closure[module] = allowed
    return closure


def classify(rel):
    """(module, is public header, is private detail header) of a path relative to the root."""
    parts = rel.parts
    if parts[0] == "include" and len(parts) > 3 and parts[1] == "beamtrace":
        return parts[2], True, False
    if parts[0] == "src" and len(parts) > 2:
        return parts[1], False, "detail" in parts[2:-1]
    if parts[0] == "bench":
        return ("harness" if len(parts) > 2 and parts[1] == "harness" else "bench"), False, False
    if parts[0] in ("apps", "examples", "fuzz"):
        return parts[0], False, False
    return None, False, False


def resolve(root, including, name):
    """The file that `#include "name"` in `including` refers to, relative to root, or None."""
    for folder in (including.parent, *(root / d for d in SEARCH_PATH)):
        candidate = folder / name
        if candidate.is_file():
            return candidate.resolve().relative_to(root)
    return None


def check_include(root, rel, name, closure):
    """Why including `name` from `rel` is not allowed, or None when it is."""
    module, public, _ = classify(rel)
    target = resolve(root, root / rel, name)
    if target is None:
        return f'cannot find "{name}" (next to the file, or in {", ".join(SEARCH_PATH)}/)'
    other, other_public, other_detail = classify(target)
    if other is None or other not in closure:
        return f'"{name}" is in {target.parent}/, which is no module of cmake/modules.txt'
    if other != module and other not in closure[module]:
        return f'module {module} may not include module {other} ("{name}")'
    if other_detail and other != module:
        return f"module {module} may not include {target}, a private detail/ header of module {other}"
    if (public or module == "examples") and not other_public:
        what = "a public header" if public else "an example (built against an installed copy)"
        return f'{what} may only include public headers, not {target} ("{name}")'
    return None


def main():
    here = Path(__file__).resolve().parent.parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=here, help="the tree to check")
    parser.add_argument("--modules", type=Path, help="the module graph (default ROOT/cmake/modules.txt)")
    args = parser.parse_args()
    root = args.root.resolve()
    deps, library, problems = read_graph(args.modules or root / "cmake" / "modules.txt")
    closure = reachable(deps)
    files = sorted(p for d in SCANNED for p in (root / d).rglob("*") if p.suffix in EXTENSIONS and p.is_file())
    includes = 0
    for path in files:
        rel = path.relative_to(root)
        module = classify(rel)[0]
        if module not in closure:
            problems.append(f"{rel}:1: module {module} is not declared in cmake/modules.txt")
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if match:
                includes += 1
                why = check_include(root, rel, match.group(1), closure)
                if why:
                    problems.append(f"{rel}:{number}: {why}")
    for problem in problems:
        print(problem)
    if problems:
        print(f"check_includes: {len(problems)} violation(s) of the module graph", file=sys.stderr)
        return 1
    print(f"check_includes: {len(files)} files, {includes} includes, {len(library)} library modules: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
