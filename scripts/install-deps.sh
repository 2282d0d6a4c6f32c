#!/usr/bin/env bash
# Installs the Debian packages hairkit needs to build and test, and does nothing
# when they are all present. Called first by `make demo`, `make test`, `make bench`;
# with --fuzz (`make fuzz`) also clang and its runtimes; with --format (`make format`,
# `make format-check`) clang-format.
set -euo pipefail

packages=(gcc make cmake pkg-config libpng-dev zlib1g-dev libcmocka-dev)
# `hairkit view` (docs/viewer.md): GLFW and libepoxy for OpenGL 3.3 core; Xvfb, xauth and
# Mesa's software OpenGL (llvmpipe) for its headless tests (tests/cli/view.sh).
packages+=(libglfw3-dev libepoxy-dev xvfb xauth libgl1-mesa-dri)
# `make fuzz` (install-deps.sh --fuzz): clang and its runtimes (libFuzzer, ASan, UBSan).
if [ "${1:-}" = "--fuzz" ]; then
    packages+=(clang libclang-rt-dev)
fi
# `make format` and `make format-check` (install-deps.sh --format): clang-format 14 and
# python3 (scripts/fix-comment-indent.py).
if [ "${1:-}" = "--format" ]; then
    packages+=(clang-format python3)
fi

if ! command -v dpkg-query >/dev/null 2>&1; then
    echo "install-deps: this is not a Debian-like system; make sure these are installed:" >&2
    echo "  a C11 compiler with OpenMP, cmake >= 3.16, pkg-config, libpng, zlib, cmocka" >&2
    echo "  and for 'hairkit view' (optional): GLFW 3, libepoxy; for its tests Xvfb and Mesa" >&2
    exit 0
fi

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing missing packages: ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
    sudo_cmd=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo_cmd=(sudo -n)
else
    echo "install-deps: not root and no password-less sudo. Please run:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
# A fresh machine may have empty package lists: update only when the first try fails.
if ! "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}" >/dev/null; then
    "${sudo_cmd[@]}" apt-get update -q >/dev/null
    "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}" >/dev/null
fi
echo "install-deps: done" >&2
