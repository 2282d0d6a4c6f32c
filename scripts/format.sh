#!/usr/bin/env bash
# `make format`: formats every C file of the repository with .clang-format (clang-format
# 14, Debian's), then re-aligns the continuation lines of block comments that clang-format
# moved (scripts/fix-comment-indent.py). `make format-check` (run by .ci/run) fails on
# any file this would change.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.c' '*.h')
if [ "${1:-}" = "--check" ]; then
    clang-format --dry-run -Werror "${files[@]}"
    echo "format-check: ${#files[@]} files formatted as .clang-format says"
    exit 0
fi
clang-format -i "${files[@]}"
python3 scripts/fix-comment-indent.py "${files[@]}"
clang-format -i "${files[@]}"
python3 scripts/fix-comment-indent.py "${files[@]}"
