#!/usr/bin/env python3
"""spirv_precise_test.py DUMP GLSLANG OUT_DIR — `precise` reaches the SPIR-V.

The values whose rounding decides something discrete (the whole turns of a
closed curve, the migration period and flyaway cell of a fiber point, the
LoD fiber count and subdivisions; common/prelude.h: FT_PRECISE) must be
computed without contraction into fused multiply-adds, or the two sides may
pick different periods. This compiles every resolved shader stage
(ft_shader_dump) to SPIR-V under OpenGL semantics (glslangValidator -G -H),
follows each store into a variable of the list below back through the
arithmetic that produces it (within its function, up to loads, calls and
constants), and requires the NoContraction decoration on every float
add/sub/mul/div there. Each name must be found with at least one such
operation, so the check cannot pass vacuously (issue 14, deliverable 12).
"""
import os
import re
import subprocess
import sys
import tempfile

# (function, variable) -> what it decides. Each must be found.
REQUIRED = {
    ("ftWholeTurnRate", "turns"): "fiber_geometry.h: whole turns of a closed curve",
    ("ftTwistRates", "periods"): "fiber_geometry.h: migration periods of a closed curve",
    ("ftPlyFrame", "twistTurns"): "fiber_geometry.h: ply twist phase",
    ("ftPeriodPhase", "phase"): "fiber_geometry.h: migration period index",
    ("ftPeriodPhase", "scaled"): "fiber_geometry.h: flyaway cell index",
    ("ftFiberPosition", "fiberTurns"): "fiber_geometry.h: fiber twist phase",
    ("ftLengthAt", "s"): "fiber_generation.h: length coordinate of a vertex",
    ("ftSampleT", "t"): "fiber_vertex.h: curve parameter of a yarn sample",
    ("ftSubdivisionBound", "accel"): "lod.h: curvature bound of the subdivisions",
    ("ftSubdivisionBound", "n"): "lod.h: subdivision estimate",
    ("ftDecideSegment", "scale"): "lod.h: λ² of eq. 4",
    ("ftDecideSegment", "fibers"): "lod.h: fibers drawn",
}
ARITH = {"FAdd", "FSub", "FMul", "FDiv", "VectorTimesScalar", "FNegate"}
# Operations the walk goes through (their operands feed the stored value).
THROUGH = ARITH | {"CompositeExtract", "CompositeConstruct", "VectorShuffle", "ConvertUToF", "ConvertSToF",
                   "ExtInst", "Select", "CopyObject"}

INSTR = re.compile(r"^\s*(\d+)(?:\([^)]*\))?:\s*\S+\s+(\w+)\s*(.*)$")  # long labels run into the type
NAME = re.compile(r'^\s*Name (\d+)\s+"([^"]*)"')
DECOR = re.compile(r"^\s*Decorate (\d+) NoContraction")
STORE = re.compile(r"^\s*Store (\d+)(?:\([^)]*\))? (\d+)")
ID = re.compile(r"(\d+)(?:\([^)]*\))?")


def check_stage(text, found, problems, stage):
    names, nocontract, defs, stores = {}, set(), {}, []
    function = None  # id of the function being read
    for line in text.splitlines():
        if m := NAME.match(line):
            names[int(m.group(1))] = m.group(2)
        elif m := DECOR.match(line):
            nocontract.add(int(m.group(1)))
        elif m := STORE.match(line):
            stores.append((function, int(m.group(1)), int(m.group(2))))
        elif line.strip() == "FunctionEnd":
            function = None
        elif m := INSTR.match(line):
            op, rest = m.group(2), m.group(3)
            if op == "Function":
                function = int(m.group(1))
            tokens = rest.split()
            if op == "ExtInst":
                tokens = tokens[2:]  # set and instruction number are not operands
            defs[int(m.group(1))] = (op, [int(t.group(1)) for t in map(ID.fullmatch, tokens) if t])
    for fn, var, value in stores:
        # SPIR-V function names are mangled: "ftPeriodPhase(struct-...;".
        key = (names.get(fn, "").split("(")[0], names.get(var))
        if key not in REQUIRED:
            continue
        name = f"{key[0]}: {key[1]}"
        arith, stack, seen = 0, [value], set()
        while stack:
            i = stack.pop()
            if i in seen or i not in defs:
                continue
            seen.add(i)
            op, operands = defs[i]
            if op not in THROUGH:
                continue
            if op in ARITH:
                arith += 1
                if i not in nocontract:
                    problems.append(f"{stage}: %{i} {op} feeding '{name}' ({REQUIRED[key]}) lacks NoContraction")
            stack.extend(operands)
        if arith:
            found.add(key)


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    dump, validator, out = sys.argv[1:]
    subprocess.run([dump, "--out", out], check=True, stdout=subprocess.DEVNULL)
    plain = os.path.join(out, "plain")
    found, problems, stages = set(), [], 0
    for f in sorted(os.listdir(plain)):
        m = re.match(r".*\.(vert|tesc|tese|geom|frag|comp)\.glsl$", f)
        if not m:
            continue
        path = os.path.join(plain, f)
        with open(path) as fh:
            if "FT_PRECISE" not in fh.read():
                continue
        with tempfile.TemporaryDirectory() as tmp:
            r = subprocess.run([validator, "-G", "--aml", "-H", "-S", m.group(1), path, "-o",
                                os.path.join(tmp, "out.spv")], capture_output=True, text=True)
        if r.returncode != 0:
            # OpenGL SPIR-V lacks a few GLSL built-ins (gl_NumSamples); such a
            # stage is left out, and every value above must still be found.
            print(f"skip {f}: not compilable as OpenGL SPIR-V ({r.stdout.splitlines()[1] if r.stdout.count(chr(10)) else r.stdout})")
            continue
        stages += 1
        check_stage(r.stdout, found, problems, f)
    for key in sorted(set(REQUIRED) - found):
        problems.append(f"'{key[0]}: {key[1]}' ({REQUIRED[key]}): no store with float arithmetic found in any "
                        "stage (renamed? then update REQUIRED)")
    if stages == 0:
        problems.append("no shader stage uses FT_PRECISE")
    for p in problems:
        print("FAIL", p)
    print(f"{stages} stages, {len(found)}/{len(REQUIRED)} precise values checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
