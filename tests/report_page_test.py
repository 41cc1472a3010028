#!/usr/bin/env python3
"""Loads a report's index.html in headless Chromium and checks it as a reader
would get it: the page's script ran (data-ready), every thumbnail loaded
(data-broken-images="0"), no console message (errors, uncaught exceptions),
one row per case of report.json with failures first, and the verdict line
agrees with report.json.

usage: report_page_test.py CHROMIUM REPORT_DIR [--screenshot OUT.png]
(--screenshot also writes a 1400-pixel-wide picture of the page's top, as in
docs/images/report.png.)
"""
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile


def chromium_args(chromium, profile):
    return [chromium, "--headless", "--disable-gpu", "--no-sandbox", "--no-first-run",
            "--user-data-dir=" + profile, "--virtual-time-budget=10000"]


def main():
    args = sys.argv[1:]
    shot = None
    if "--screenshot" in args:
        i = args.index("--screenshot")
        shot = args[i + 1]
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    chromium, report = args[0], pathlib.Path(args[1])
    if not shutil.which(chromium):
        sys.exit(f"{chromium}: not found; install Chromium (scripts/install-deps.sh installs the Debian package)")
    page = (report / "index.html").resolve()
    data = json.loads((report / "report.json").read_text())
    bad = []
    with tempfile.TemporaryDirectory() as profile:
        run = subprocess.run(chromium_args(chromium, profile) + ["--enable-logging=stderr", "--v=0", "--dump-dom",
                                                                 page.as_uri()],
                             capture_output=True, text=True, timeout=120)
        if run.returncode != 0:
            bad.append(f"chromium exited with {run.returncode}:\n{run.stderr[-2000:]}")
        dom = run.stdout
        console = [l for l in run.stderr.splitlines() if ":CONSOLE" in l or "Uncaught" in l]
        bad += [f"console: {l}" for l in console]
        body = re.search(r"<body([^>]*)>", dom)
        attrs = body.group(1) if body else ""
        if 'data-ready="1"' not in attrs:
            bad.append(f"the page's script did not finish (body attributes: {attrs.strip()!r})")
        if 'data-broken-images="0"' not in attrs:
            bad.append(f"thumbnails failed to load (body attributes: {attrs.strip()!r})")
        rows = re.findall(r"<tr class=\"case (passed|failed)\"[^>]*data-name=\"([^\"]*)\"", dom)
        cases = data.get("cases") or []
        if len(rows) != len(cases):
            bad.append(f"{len(rows)} case rows on the page, {len(cases)} cases in report.json")
        seen_pass = False
        for state, name in rows:
            if state == "passed":
                seen_pass = True
            elif seen_pass:
                bad.append(f"failed case {name} is listed after a passed one")
        failed = sum(1 for c in cases if not c.get("pass"))
        if sorted(n for s, n in rows if s == "failed") != sorted(data.get("failed_cases") or []):
            bad.append("the failed rows differ from report.json's failed_cases")
        header = re.search(r"<header id=\"verdict\"[^>]*>(.*?)</header>", dom, re.S)
        want = f"all {len(cases)} cases passed" if failed == 0 else f"{failed} of {len(cases)} cases FAILED"
        if not header or want not in header.group(1):
            bad.append(f"verdict header does not say {want!r}")
        for key in ("commit", "date_utc", "command_line"):
            if not isinstance(data.get(key), str) or not data[key].strip():
                bad.append(f"report.json lacks {key}")
        if data.get("commit") and data["commit"] not in dom:
            bad.append(f"the page does not show the commit {data['commit']}")
        if shot:
            subprocess.run(chromium_args(chromium, profile) + ["--hide-scrollbars", "--window-size=1400,1400",
                                                               "--screenshot=" + str(pathlib.Path(shot).resolve()),
                                                               page.as_uri()],
                           capture_output=True, text=True, timeout=120, check=True)
    print("\n".join(bad) or f"report page ok: {len(rows)} cases, {failed} failed, no console messages, "
          f"all images loaded")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
