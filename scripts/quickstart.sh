#!/usr/bin/env bash
# Quick start (1): install what is missing, build, and run the main job —
# `fibertwin validate` on the built-in default scene. Report: ./fibertwin-report/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
./build/release/cli/fibertwin validate --report fibertwin-report "$@"
