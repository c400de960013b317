#!/usr/bin/env python3
"""Fails if an #include points up uwmetric's layers (docs/architecture.md).

    python3 scripts/check_layering.py [ROOT]     # check the tree (default: .)
    python3 scripts/check_layering.py --graph    # the folder-level include graph
    python3 scripts/check_layering.py --self-test

Every folder of C++ sources sits in one layer of LAYERS, lowest first. Product
code (libraries and executables) may include its own folder and the folders
of lower layers, never a sibling of its own layer nor anything above it, and
never a test header. Test code -- *_test.cc, *_test.h, *_testing.{h,cc},
test_*.h and everything under tests/ and bench/ -- may in addition use the
simulator (sim/, experiments/) and tests/support/ as fixtures.

Prints one line per offending #include (file:line: what and why) and exits 1;
exits 0 with a one-line summary otherwise. A folder that is in no layer is an
error too: a new folder must say where it belongs.
"""
import collections
import os
import re
import sys
import tempfile

# Lowest first. Folders in one entry are siblings: independent of each other.
LAYERS = [
    ["common"],
    ["colmap_plugins/cameras"],
    ["colmap_plugins/scene"],
    # Alignment to navigation reads it (model_alignment), hence above nav/.
    ["colmap_plugins/nav", "colmap_plugins/dense"],
    ["colmap_plugins/align"],
    ["colmap_plugins/ba"],
    ["laserscale"],
    ["calib", "report"],
    ["sim"],
    ["experiments"],
    ["colmap_plugins/exe", "laserscale/exe", "calib/exe", "sim/exe"],
]
# Test code may use these as fixtures, wherever it lives.
TEST_FIXTURES = ["sim", "experiments", "tests/support"]
# Only tests and benchmarks live here; they sit above everything.
TOP = ["tests", "bench"]
SOURCE_SUFFIXES = (".h", ".cc")
INCLUDE = re.compile(r'\s*#\s*include\s+"([^"]+)"')


def folder_of(path, folders):
    """The longest listed folder that contains `path`, or None."""
    best = None
    for folder in folders:
        if path == folder or path.startswith(folder + "/"):
            if best is None or len(folder) > len(best):
                best = folder
    return best


def is_test_code(path):
    name = os.path.basename(path)
    stem = os.path.splitext(name)[0]
    return (stem.endswith("_test") or stem.endswith("_testing") or
            stem.startswith("test_") or
            folder_of(path, TOP) is not None)


class Layering:
    def __init__(self):
        self.rank = {}
        for rank, folders in enumerate(LAYERS):
            for folder in folders:
                self.rank[folder] = rank
        self.folders = list(self.rank) + TOP + ["tests/support"]

    def folder(self, path):
        return folder_of(path, self.folders)

    def why_not(self, source, target):
        """None if `source` may include `target`, else the reason."""
        from_folder = self.folder(source)
        to_folder = self.folder(target)
        if to_folder is None:
            return f"{target} is in no layer of scripts/check_layering.py"
        if is_test_code(target) and not is_test_code(source):
            return "product code includes a test header"
        if from_folder in TOP or from_folder == "tests/support":
            return None
        if is_test_code(source) and folder_of(target, TEST_FIXTURES):
            return None
        if to_folder == "tests/support" or to_folder in TOP:
            return f"{to_folder}/ is for tests only"
        if from_folder == to_folder:
            return None
        if self.rank[to_folder] > self.rank[from_folder]:
            return f"{from_folder}/ includes {to_folder}/, a higher layer"
        if self.rank[to_folder] == self.rank[from_folder]:
            return (f"{from_folder}/ includes its sibling {to_folder}/ "
                    "(same layer: keep them independent)")
        return None


def sources(root):
    for directory, subdirectories, files in os.walk(root):
        relative = os.path.relpath(directory, root)
        subdirectories[:] = sorted(
            d for d in subdirectories
            if not d.startswith(".") and d not in ("build", "out") and
            not (relative == "." and d.startswith("build")))
        for name in sorted(files):
            if name.endswith(SOURCE_SUFFIXES):
                path = os.path.normpath(os.path.join(relative, name))
                yield path


def check(root):
    layering = Layering()
    problems = []
    edges = collections.Counter()
    for path in sources(root):
        folder = layering.folder(path)
        if folder is None:
            problems.append(f"{path}: its folder is in no layer of "
                            "scripts/check_layering.py (add it to LAYERS)")
            continue
        with open(os.path.join(root, path), errors="replace") as text:
            for number, line in enumerate(text, 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                target = match.group(1)
                if not os.path.exists(os.path.join(root, target)):
                    # A header next to the file, or a generated one.
                    continue
                to_folder = layering.folder(target)
                if to_folder and to_folder != folder:
                    edges[(folder, to_folder,
                           "test" if is_test_code(path) else "product")] += 1
                reason = layering.why_not(path, target)
                if reason:
                    problems.append(
                        f'{path}:{number}: #include "{target}": {reason}')
    return problems, edges


def self_test():
    """The check itself must be able to fail."""
    cases = {
        # (file, include) -> is it refused?
        ("laserscale/a.cc", "sim/world.h"): True,
        ("laserscale/a_test.cc", "sim/world.h"): False,
        ("common/util/a.cc", "colmap_plugins/scene/model.h"): True,
        ("colmap_plugins/nav/a.cc", "colmap_plugins/align/sim3.h"): True,
        ("colmap_plugins/ba/a.cc", "colmap_plugins/align/sim3.h"): False,
        ("calib/a.cc", "report/html.h"): True,
        ("report/a.cc", "common/mesh/test_meshes.h"): True,
        ("report/a_test.cc", "common/mesh/test_meshes.h"): False,
        ("colmap_plugins/scene/a.cc", "tests/support/process.h"): True,
        ("colmap_plugins/exe/a.cc", "report/html.h"): False,
        ("tests/a_test.cc", "calib/board.h"): False,
        ("newfolder/a.cc", "common/util/error.h"): True,
    }
    failures = 0
    with tempfile.TemporaryDirectory() as root:
        for (source, target), refused in cases.items():
            for path in (source, target):
                os.makedirs(os.path.join(root, os.path.dirname(path)),
                            exist_ok=True)
                open(os.path.join(root, path), "a").close()
        for (source, target), refused in cases.items():
            with open(os.path.join(root, source), "a") as text:
                text.write(f'#include "{target}"\n')
        problems, _ = check(root)
        for (source, target), refused in cases.items():
            found = any(p.startswith(source + ":") and target in p or
                        p.startswith(source + ": its folder")
                        for p in problems)
            if found != refused:
                failures += 1
                print(f"self-test: {source} -> {target}: expected "
                      f"{'refused' if refused else 'allowed'}")
    print(f"check_layering self-test: {len(cases) - failures} passed, "
          f"{failures} failed")
    return 1 if failures else 0


def main(argv):
    if "--self-test" in argv:
        return self_test()
    paths = [a for a in argv[1:] if not a.startswith("--")]
    root = paths[0] if paths else "."
    problems, edges = check(root)
    if "--graph" in argv:
        for (source, target, kind), count in sorted(edges.items()):
            print(f"{kind:8s} {source:22s} -> {target:22s} {count}")
    for problem in problems:
        print(problem)
    if problems:
        print(f"check_layering: {len(problems)} #include(s) against the "
              "layers (docs/architecture.md)")
        return 1
    print(f"check_layering: every #include follows the layers "
          f"({sum(edges.values())} across folders)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
