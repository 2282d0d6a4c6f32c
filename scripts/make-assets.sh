#!/usr/bin/env bash
# Remakes assets/head.obj, assets/wick.obj and assets/wick-200.obj with tools/make_assets.c.
# `scripts/make-assets.sh --check` only tells whether the committed assets are what
# the generator makes (exit 1 when they differ).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/make_assets ] || make build
if [ "${1:-}" = "--check" ]; then
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    build/make_assets "$tmp"
    cmp assets/head.obj "$tmp/head.obj" && cmp assets/wick.obj "$tmp/wick.obj" && cmp assets/wick-200.obj "$tmp/wick-200.obj"
    echo "assets are up to date"
else
    build/make_assets assets
fi
