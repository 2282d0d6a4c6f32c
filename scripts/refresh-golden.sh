#!/usr/bin/env bash
# Stores the renderer's pictures of tests/test_golden.c as the new golden pictures in
# tests/golden/ (tests/README.md, "Golden pictures"). Run it only for a change that is
# meant to change the pictures, look at them, and say in the commit why they changed.
# BUILD (default build) is the build folder to use.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build}
[ -d "$build" ] || make build
cmake --build "$build" --target test_golden > /dev/null
HK_REFRESH_GOLDEN="$PWD/tests/golden" "$build/test_golden" | grep '^wrote' || true
ls -l tests/golden/*.png
git status --short tests/golden
