#!/usr/bin/env python3
"""Mutation testing of fibertwin's checks (python3 standard library only).

Plants one operator mutation at a time in a private copy of the source tree
(sign flips, +-1 on integer literals and loop bounds, swapped vector
components and call arguments, constants x2 and x0.5, dropped terms, < <-> <=),
rebuilds only what the mutated file feeds (in that copy's own build folder),
runs the checks that can see it with time limits, and writes a table of killed
and surviving mutants by file (markdown + JSON).

Checks, recorded separately for every mutant so that each kind's power shows:
  harness  `fibertwin validate` on the built-in scene (fast subset: --no-images
           --yarn cotton1, filtered to the cases the file feeds: RULES)
  units    the unit tests of the file's algorithm (RULES: fiber_math_test,
           bcsdf_test, fiber_trace_test, flip_test, self_shadow_test, ...)
  oracle   tests/oracle_fiber_test and tests/oracle_knit_test (no code shared
           with common/)
Shader mutants need no rebuild: FT_SHADER_DIR points fibertwin at the copy's
gpu/shaders (gpu/shader_library.cpp); only the harness sees shaders.

Usage:
  python3 scripts/mutation_test.py --list                     # every candidate mutant
  python3 scripts/mutation_test.py --max-mutants 40 --seed 1  # a deterministic sample
  python3 scripts/mutation_test.py --files 'gpu/shaders/fiber_*.glsl' --max-mutants 20
  python3 scripts/mutation_test.py --only 'fiber_geometry.h:196:45:const' --max-mutants 0
  python3 scripts/mutation_test.py --changed-since origin/main --max-mutants 30  # your own change
Outputs (default build/mutation/): report.md, report.json, log.txt.
"""
import argparse
import fnmatch
import json
import os
import random
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_FILES = ["common/*.h", "gpu/shaders/*.glsl", "reference/*.cpp", "scene/*.cpp", "image/*.cpp"]
FOLDERS = ["common", "gpu/shaders", "reference", "scene", "image"]
# Test-only shaders (GL smoke test, layout probe): not part of the product.
EXCLUDE = ["gpu/shaders/smoke.comp.glsl", "gpu/shaders/layout_probe.comp.glsl"]

# Lines never mutated: preprocessor lines, layout asserts, version/extension/layout qualifiers.
SKIP_LINE = re.compile(r"^\s*(#|FT_ASSERT_|static_assert|layout\s*\(|precision\s)")
FLOAT_LIT = re.compile(r"(?<![\w.])(\d+\.\d*(?:[eE][-+]?\d+)?|\d*\.\d+(?:[eE][-+]?\d+)?)(f?)(?![\w.])")
INT_LIT = re.compile(r"(?<![\w.])(\d+)(u?)(?![\w.])")
SWIZZLE = re.compile(r"\.(x|y|z)\b")
CALL2 = re.compile(r"\b([A-Za-z_]\w*)\(\s*([A-Za-z_][\w.]*)\s*,\s*([A-Za-z_][\w.]*)\s*\)")
DROP_TERM = re.compile(r"\s[+-]\s+([A-Za-z_][\w.]*(?:\([^()]*\))?)(?=\s*[;)])")
KEYWORDS = {"if", "for", "while", "return", "switch", "sizeof", "static_cast", "max", "min"}


class Mutant:
    def __init__(self, path, line, col, op, old, new, text):
        self.path, self.line, self.col, self.op, self.old, self.new = path, line, col, op, old, new
        self.text = text  # the mutated line

    def key(self):
        return (self.path, self.line, self.col, self.op, self.new)

    def ident(self):
        return f"{self.path}:{self.line}:{self.col}:{self.op}"


def strip_comment(line):
    i = line.find("//")
    return line if i < 0 else line[:i]


def fault_regions(lines):
    """Line numbers (1-based) inside `#ifdef FT_FAULT_*` branches: never compiled
    in a normal build, so mutants there would be equivalent by construction."""
    skip, stack = set(), []
    for n, raw in enumerate(lines, 1):
        s = raw.strip()
        if s.startswith("#if"):
            stack.append(bool(re.match(r"#\s*if(def)?\s+.*FT_FAULT_", s)) and "!" not in s)
        elif s.startswith("#else") or s.startswith("#elif"):
            if stack:
                stack[-1] = False
        elif s.startswith("#endif"):
            if stack:
                stack.pop()
        elif any(stack):
            skip.add(n)
    return skip


def candidates_in(path):
    rel = os.path.relpath(path, ROOT)
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    skip = fault_regions(lines)
    glsl = rel.endswith(".glsl") or rel.startswith("common/")
    out = []
    in_block = False
    for n, raw in enumerate(lines, 1):
        code = strip_comment(raw)
        if "/*" in code:
            in_block = "*/" not in code[code.index("/*"):]
            code = code[: code.index("/*")]
        elif in_block:
            if "*/" in code:
                in_block = False
            continue
        # Lines with string literals are messages and names: mutants there are cosmetic.
        if n in skip or SKIP_LINE.match(code) or not code.strip() or '"' in code:
            continue

        def add(op, start, end, new):
            old = code[start:end]
            if old == new:
                return
            mutated = raw[:start] + new + raw[end:]
            out.append(Mutant(rel, n, start + 1, op, old, new, mutated))

        # Relational: < <-> <=, > <-> >=, written with a space on each side as the
        # code style writes comparisons (template brackets, <<, >>, -> are not).
        for m in re.finditer(r"(?<= )(<=|>=|<|>)(?= )", code):
            add("rel", m.start(), m.end(), {"<": "<=", "<=": "<", ">": ">=", ">=": ">"}[m.group(1)])
        # Sign flips of binary + and - (spaced, as the code style writes them).
        for m in re.finditer(r"(?<=[\w)\]]) ([+-]) (?=[\w(.])", code):
            add("sign", m.start() + 1, m.start() + 2, "-" if m.group(1) == "+" else "+")
        # Unary minus dropped.
        for m in re.finditer(r"(?<=[(,=*/] )-(?=[A-Za-z_(])|(?<=[(,])-(?=[A-Za-z_(])", code):
            add("neg", m.start(), m.end(), "")
        # Constants x2 and x0.5 (floating literals).
        for m in FLOAT_LIT.finditer(code):
            lit, suffix = m.group(1), m.group(2)
            if float(lit) == 0.0:
                continue  # 0 × 2 = 0: equivalent by construction
            two = "2.0f" if (suffix or glsl) else "2.0"
            half = "0.5f" if (suffix or glsl) else "0.5"
            add("const*2", m.start(), m.end(), f"({lit}{suffix} * {two})")
            add("const/2", m.start(), m.end(), f"({lit}{suffix} * {half})")
        # +-1 on integer literals (indices, loop bounds, counts).
        for m in INT_LIT.finditer(code):
            value, suffix = int(m.group(1)), m.group(2)
            if value > 1 << 20:
                continue
            add("int+1", m.start(), m.end(), f"{value + 1}{suffix}")
            if value > 0:
                add("int-1", m.start(), m.end(), f"{value - 1}{suffix}")
        # Swapped vector components.
        for m in SWIZZLE.finditer(code):
            add("swizzle", m.start(), m.end(), "." + {"x": "y", "y": "z", "z": "x"}[m.group(1)])
        # Swapped arguments of two-argument calls.
        for m in CALL2.finditer(code):
            if m.group(1) in KEYWORDS - {"max", "min"} or m.group(2) == m.group(3):
                continue
            add("swap-args", m.start(2), m.end(3), f"{m.group(3)}, {m.group(2)}")
        # Dropped terms: "a + b;" -> "a;".
        for m in DROP_TERM.finditer(code):
            add("drop-term", m.start(), m.end(), "")
    return out


def all_candidates(globs):
    files = []
    for g in globs:
        for root, _, names in os.walk(ROOT):
            if "/build" in root or "/.git" in root:
                continue
            for name in names:
                rel = os.path.relpath(os.path.join(root, name), ROOT)
                if fnmatch.fnmatch(rel, g) and rel not in files and rel not in EXCLUDE:
                    files.append(rel)
    files.sort()
    cands = []
    for f in files:
        cands.extend(candidates_in(os.path.join(ROOT, f)))
    cands.sort(key=Mutant.key)
    return cands


def changed_lines(rev):
    """{path: set of line numbers} added or changed in the working tree since `rev`."""
    diff = subprocess.run(["git", "diff", "-U0", rev, "--"], cwd=ROOT, stdout=subprocess.PIPE, text=True,
                          check=True).stdout
    out, path = {}, None
    for line in diff.split("\n"):
        if line.startswith("+++ "):
            path = line[6:] if line.startswith("+++ b/") else None
        m = re.match(r"@@ -\S+ \+(\d+)(?:,(\d+))? @@", line)
        if m and path:
            start, count = int(m.group(1)), int(m.group(2) or 1)
            out.setdefault(path, set()).update(range(start, start + count))
    return out


def folder_of(rel):
    for f in FOLDERS:
        if rel.startswith(f + "/"):
            return f
    return os.path.dirname(rel)


def sample(cands, n, seed):
    """Deterministic: equal shares per folder (the rest to the folders that have
    more), each share drawn with random.Random(seed) from that folder's mutants."""
    if n <= 0 or n >= len(cands):
        return list(cands)
    groups = {}
    for c in cands:
        groups.setdefault(folder_of(c.path), []).append(c)
    rng = random.Random(seed)
    names = sorted(groups)
    share = {g: 0 for g in names}
    left = n
    while left > 0:
        open_groups = [g for g in names if share[g] < len(groups[g])]
        if not open_groups:
            break
        for g in open_groups:
            if left == 0:
                break
            share[g] += 1
            left -= 1
    chosen = []
    for g in names:
        chosen.extend(rng.sample(groups[g], share[g]))
    chosen.sort(key=Mutant.key)
    return chosen


# Which checks can see a mutant, by file: the first rule whose pattern matches
# the path (relative to the repository root) gives the harness cases and the
# unit tests (oracles included) to run. One table, so a new algorithm's files
# are mapped by one line here.
#   (path regex, harness filter or None, unit tests)
RULES = [
    (r"core_texture", "^(appearance/)?core-texture/", ["core_texture_test"]),
    (r"self_shadow", "^(selfshadow|appearance)/", ["self_shadow_test"]),
    (r"ambient_occlusion", "^ao/", ["ambient_occlusion_test"]),
    # The yarn shadow map (000 §4.1), its lookup's filter, and PCSS (001 §4.5), which reads the same maps.
    (r"shadow_map|shadow_scene|pcss", "^(shadowmap|pcss)/", ["pcss_test"]),
    # Dual scattering (001 §4.1) and its correction ξ (§4.3): ξ's bake reads the DS tables.
    (r"ds_correction", "^xi/", ["ds_correction_test"]),
    (r"dual_scattering", "^(ds|xi)/", ["dual_scattering_test", "ds_correction_test"]),
    # The bake runner: its own tests (MPI byte-identity included).
    (r"^bake/", None, ["bake_test"]),
    (r"yarn_density", "^(selfshadow|ao)/", ["yarn_density_test", "self_shadow_test", "ambient_occlusion_test"]),
    # The BCSDF and its tables: its cases (oracle included), the shading cases, its unit test.
    (r"bcsdf", "^(bcsdf|shading)/", ["bcsdf_test", "fiber_trace_test"]),
    # Occlusion culling (common/occlusion_cull.h, the pyramid kernel, the per-sample depth read-back):
    # the frame with and without it, and the occluders against the frame sample by sample;
    # two-pass culling (ftStripKey, the same pyramid) against one pass, before and after a turn.
    (r"occlusion_(cull|pyramid)|sample_depth_read|two_pass", "^shading/(occlusion|two-pass)-cull/", ["occlusion_cull_test"]),
    # Deferred shading's kernels (the compaction also marks the strips two-pass culling reuses).
    (r"fiber_(compact|shade)|deferred_resources", "^shading/", ["fiber_trace_test"]),
    # The shaded frame: fragment shading, the renderer, the shading inputs, the ground truth.
    (r"fiber_shading\.h|fiber_strip\.(frag|geom)|fiber_renderer|shading_inputs|fiber_trace|lighting\.cpp|fabric\.cpp",
     "^(shading|appearance|closeup)/|strip-width", ["fiber_trace_test", "bcsdf_test"]),
    # Image metrics: FLIP/RMSE decide every shading case; their own tests first.
    (r"^image/", "^shading/", ["flip_test", "image_io_test"]),
    (r"^scene/bcc_reader", "fiber|frames|closeup|strip-width", ["bcc_reader_test", "fiber_math_test"]),
    (r"^scene/yarn_preset", "fiber|frames|closeup|strip-width", ["yarn_preset_test", "fiber_math_test"]),
    (r"^scene/camera", "fiber|frames|closeup|strip-width", ["camera_test"]),
    (r"knit", "knit", ["knit_solver_test", "oracle_knit_test"]),
    (r"^common/(prelude|constants)\.h$", ".", ["fiber_math_test", "fiber_reference_test", "oracle_fiber_test",
                                                "knit_solver_test", "oracle_knit_test"]),
    (r".", "fiber|frames|closeup|strip-width", ["fiber_math_test", "fiber_reference_test", "oracle_fiber_test"]),
]
ORACLES = {"oracle_fiber_test", "oracle_knit_test"}


def checks_for(rel, args, copy, build):
    """(kind, command, env) of every check that can see a mutant in `rel`."""
    fib = os.path.join(build, "cli", "fibertwin")
    tests = os.path.join(build, "tests")
    report = os.path.join(build, "mutation-report")
    filt, units = next((f, u) for pattern, f, u in RULES if re.search(pattern, rel))
    shader = rel.startswith("gpu/shaders/")
    # Shader mutants need no rebuild: FT_SHADER_DIR points the program at the copy's shaders.
    env = {"FT_SHADER_DIR": os.path.join(copy, "gpu", "shaders")} if shader else {}
    out = []
    if filt:
        out.append(("harness", [fib, "validate", "--no-images", "--filter", filt, "--report", report]
                    + args.validate_args.split(), env))
    if not shader:  # only the harness runs shaders
        for u in units:
            out.append(("oracle" if u in ORACLES else "units", [os.path.join(tests, u), "--gtest_brief=1"], {}))
    return out


def run(cmd, timeout, env=None, cwd=None, log=None):
    e = dict(os.environ)
    if env:
        e.update(env)
    t = time.time()
    try:
        p = subprocess.run(cmd, cwd=cwd or ROOT, env=e, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, text=True, errors="replace")
        rc, out = p.returncode, p.stdout
    except subprocess.TimeoutExpired as ex:
        rc, out = "timeout", (ex.stdout or "") if isinstance(ex.stdout, str) else ""
    if log:
        log.write(f"$ {' '.join(cmd)}  [{rc}, {time.time() - t:.1f} s]\n{out[-3000:]}\n")
        log.flush()
    return rc, out


TARGETS = ["fibertwin"] + sorted({u for _, _, units in RULES for u in units})


def prepare_copy(args, log):
    """A copy of the tracked (and untracked, not ignored) files and its release build."""
    copy = os.path.join(args.work, "src")
    files = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                           stdout=subprocess.PIPE, text=True, check=True).stdout.split("\n")
    for rel in filter(None, files):
        src, dst = os.path.join(ROOT, rel), os.path.join(copy, rel)
        if not os.path.isfile(src):
            continue
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        with open(src, "rb") as a:
            data = a.read()
        if not os.path.exists(dst) or open(dst, "rb").read() != data:
            with open(dst, "wb") as b:
                b.write(data)
    build = os.path.join(copy, "build", "release")
    launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"] if shutil.which("ccache") else []
    rc, _ = run(["cmake", "--preset", "release"] + launcher, 600, cwd=copy, log=log)
    if rc != 0:
        sys.exit("mutation_test: configuring the copy failed (see log.txt)")
    rc, _ = run(["cmake", "--build", "--preset", "release", "--target"] + TARGETS, args.build_timeout, cwd=copy, log=log)
    if rc != 0:
        sys.exit("mutation_test: the unmutated copy does not build (see log.txt)")
    return copy, build


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--files", action="append", help="glob relative to the repository root (repeatable); default: "
                    + " ".join(DEFAULT_FILES))
    ap.add_argument("--max-mutants", type=int, default=40, help="sample size (0 = all candidates)")
    ap.add_argument("--seed", type=int, default=1, help="sampling seed (deterministic)")
    ap.add_argument("--list", action="store_true", help="list the (sampled) mutants and exit")
    ap.add_argument("--changed-since", metavar="REV",
                    help="only lines added or changed since git revision REV (e.g. origin/main, HEAD~1), "
                    "working tree included: mutants of your own change")
    ap.add_argument("--only", help="regex on mutant ids (file:line:col:op), applied before sampling; "
                    "e.g. rerun the survivors of a report after adding checks")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "mutation"), help="copy, build and reports")
    ap.add_argument("--validate-args", default="--yarn cotton1", help="extra `fibertwin validate` arguments")
    ap.add_argument("--check-timeout", type=int, default=300, help="seconds per check")
    ap.add_argument("--build-timeout", type=int, default=1800, help="seconds per rebuild")
    ap.add_argument("--budget", type=int, default=0, help="stop starting mutants after this many seconds (0: none)")
    args = ap.parse_args()
    args.work = os.path.abspath(args.work)

    cands = all_candidates(args.files or DEFAULT_FILES)
    if args.changed_since:
        changed = changed_lines(args.changed_since)
        cands = [c for c in cands if c.line in changed.get(c.path, ())]
    if args.only:
        cands = [c for c in cands if re.search(args.only, c.ident())]
    chosen = sample(cands, args.max_mutants, args.seed)
    if args.list:
        for c in chosen:
            print(f"{c.ident():55s} {c.old!r} -> {c.new!r}")
        print(f"{len(chosen)} of {len(cands)} candidates", file=sys.stderr)
        return 0

    os.makedirs(args.work, exist_ok=True)
    log = open(os.path.join(args.work, "log.txt"), "w")
    t0 = time.time()
    copy, build = prepare_copy(args, log)
    results = []
    # Baseline: every check passes on the unmutated copy (else nothing can be concluded).
    for rel in sorted({c.path for c in chosen}):
        for kind, cmd, env in checks_for(rel, args, copy, build):
            rc, _ = run(cmd, args.check_timeout, env, cwd=copy, log=log)
            if rc != 0:
                sys.exit(f"mutation_test: baseline check fails for {rel}: {' '.join(cmd)} (see log.txt)")
    stale = False  # the build still holds the previous (restored) non-shader mutant
    for i, m in enumerate(chosen, 1):
        if args.budget and time.time() - t0 > args.budget:
            print(f"budget reached: {i - 1} of {len(chosen)} mutants run", file=sys.stderr)
            break
        path = os.path.join(copy, m.path)
        with open(path, encoding="utf-8") as f:
            original = f.read()
        lines = original.split("\n")
        lines[m.line - 1] = m.text
        entry = {"id": m.ident(), "file": m.path, "folder": folder_of(m.path), "line": m.line, "op": m.op,
                 "old": m.old, "new": m.new, "killed_by": [], "status": None}
        t = time.time()
        try:
            with open(path, "w", encoding="utf-8") as f:
                f.write("\n".join(lines))
            if not m.path.startswith("gpu/shaders/"):
                stale = True
                rc, out = run(["cmake", "--build", "--preset", "release", "--target"] + TARGETS, args.build_timeout,
                              cwd=copy, log=log)
                if rc != 0:
                    entry["status"] = "build-error" if rc != "timeout" else "build-timeout"
            elif stale:
                # Shader mutants run on the built program, whose embedded common/
                # headers must be the unmutated ones again.
                run(["cmake", "--build", "--preset", "release", "--target"] + TARGETS, args.build_timeout, cwd=copy,
                    log=log)
                stale = False
            if entry["status"] is None:
                for kind, cmd, env in checks_for(m.path, args, copy, build):
                    rc, _ = run(cmd, args.check_timeout, env, cwd=copy, log=log)
                    if rc != 0 and kind not in entry["killed_by"]:
                        entry["killed_by"].append(kind if rc != "timeout" else kind + "(timeout)")
                entry["status"] = "killed" if entry["killed_by"] else "survived"
        finally:
            with open(path, "w", encoding="utf-8") as f:
                f.write(original)
        entry["seconds"] = round(time.time() - t, 1)
        results.append(entry)
        print(f"[{i}/{len(chosen)}] {entry['status']:12s} {','.join(entry['killed_by']):24s} {m.ident()} "
              f"{m.old!r} -> {m.new!r} ({entry['seconds']} s)", flush=True)
        write_reports(args, results, len(cands), len(chosen), time.time() - t0)
    # Leave the copy's build matching the unmutated sources.
    run(["cmake", "--build", "--preset", "release", "--target"] + TARGETS, args.build_timeout, cwd=copy, log=log)
    write_reports(args, results, len(cands), len(chosen), time.time() - t0)
    return 0


def rate(killed, total):
    return f"{100.0 * killed / total:.0f} %" if total else "–"


def write_reports(args, results, candidates, sampled, seconds):
    valid = [r for r in results if r["status"] in ("killed", "survived")]
    summary = {}
    for key in ["folder", "file"]:
        table = {}
        for r in valid:
            row = table.setdefault(r[key], {"mutants": 0, "killed": 0, "killed_without_oracle": 0, "by_oracle_only": 0})
            row["mutants"] += 1
            kinds = {k.split("(")[0] for k in r["killed_by"]}
            row["killed"] += bool(kinds)
            row["killed_without_oracle"] += bool(kinds - {"oracle"})
            row["by_oracle_only"] += kinds == {"oracle"}
        summary[key] = table
    data = {"candidates": candidates, "sampled": sampled, "run": len(results), "seed": args.seed,
            "max_mutants": args.max_mutants, "files": args.files or DEFAULT_FILES, "seconds": round(seconds),
            "validate_args": args.validate_args, "summary": summary, "mutants": results}
    with open(os.path.join(args.work, "report.json"), "w") as f:
        json.dump(data, f, indent=1)
    md = [f"# Mutation testing ({len(results)} of {sampled} sampled mutants run, {candidates} candidates, "
          f"seed {args.seed}, {seconds / 60:.0f} min)", ""]
    for key in ["folder", "file"]:
        md += [f"| {key} | mutants | killed | kill rate | without oracles | killed by oracles only |",
               "| --- | ---: | ---: | ---: | ---: | ---: |"]
        tot = {"mutants": 0, "killed": 0, "killed_without_oracle": 0, "by_oracle_only": 0}
        for name, row in sorted(summary[key].items()):
            md.append(f"| {name} | {row['mutants']} | {row['killed']} | {rate(row['killed'], row['mutants'])} | "
                      f"{rate(row['killed_without_oracle'], row['mutants'])} | {row['by_oracle_only']} |")
            for k in tot:
                tot[k] += row[k]
        md.append(f"| **all** | {tot['mutants']} | {tot['killed']} | {rate(tot['killed'], tot['mutants'])} | "
                  f"{rate(tot['killed_without_oracle'], tot['mutants'])} | {tot['by_oracle_only']} |")
        md.append("")
    md += ["| mutant | change | status | killed by | s |", "| --- | --- | --- | --- | ---: |"]
    for r in results:
        change = f"`{r['old']}` → `{r['new']}`".replace("|", "\\|")
        md.append(f"| {r['id']} | {change} | {r['status']} | {', '.join(r['killed_by'])} | {r['seconds']} |")
    with open(os.path.join(args.work, "report.md"), "w") as f:
        f.write("\n".join(md) + "\n")


if __name__ == "__main__":
    sys.exit(main())
