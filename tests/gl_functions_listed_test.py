#!/usr/bin/env python3
"""Every GL entry point the project calls is listed in gpu/gl_functions.inc.

The OSMesa backend fills libepoxy's dispatch pointers from that list
(gpu/gl_context.cpp); a function missing there crashes only under
FT_GL_BACKEND=osmesa, late in a run (epoxy asserts "Couldn't find current GLX
or EGL context"). This finds them statically: every `glName(` in the C++
sources that libepoxy's header declares must be listed.

Usage: gl_functions_listed_test.py REPO_ROOT EPOXY_GL_GENERATED_H
"""
import pathlib
import re
import sys


def main():
    root = pathlib.Path(sys.argv[1])
    epoxy = pathlib.Path(sys.argv[2]).read_text()
    declared = set(re.findall(r"#define (gl[A-Z]\w*) epoxy_", epoxy))
    listed = set(re.findall(r"FT_GL_FUNCTION\((gl\w+)\)", (root / "gpu" / "gl_functions.inc").read_text()))
    used = {}
    for folder in ("gpu", "validation", "bench", "cli", "tests"):
        for path in (root / folder).rglob("*"):
            if path.suffix not in (".cpp", ".h", ".inc") or path.name == "gl_functions.inc":
                continue
            for name in re.findall(r"\b(gl[A-Z]\w*)\s*\(", path.read_text(errors="replace")):
                if name in declared:
                    used.setdefault(name, str(path.relative_to(root)))
    missing = sorted(set(used) - listed)
    if not declared:
        print(f"no gl* declarations found in {sys.argv[2]}")
        return 1
    for name in missing:
        print(f"FAIL  {name} (called in {used[name]}) is not in gpu/gl_functions.inc: OSMesa runs would crash")
    print(f"{len(used)} GL entry points called, {len(listed)} listed, {len(missing)} missing")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
