#!/usr/bin/env bash
# The pictures of docs/capture.md, "Capture, naive and inverse", side by side: the Sintel
# groom of ../shared/hair-data as captured, after 2 s of a naive forward simulation (each
# guide's natural shape the captured one, so gravity and the head bend it), and after
# 2 s of the import (the natural shape from the inverse statics). Needs ../shared/hair-data
# (never copied into this repository); says so and stops when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
hk=./build/hairkit
[ -x "$hk" ] || make build
data=../shared/hair-data
if [ ! -f "$data/SintelHairOriginal-sintel_hair.16points.tfx" ] || [ ! -f "$data/sintel-collider.obj" ]; then
    echo "make-capture-images.sh: $data is absent: no pictures made" >&2
    exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size=(--width 400 --height 300)
"$hk" import "$data/SintelHairOriginal-sintel_hair.16points.tfx" --head "$data/sintel-collider.obj" --guides 300 \
    -o "$tmp/inverse" > /dev/null
# The naive import: the same folder with each guide's natural shape (QRest) set to its
# captured shape (the Q line after it; docs/file-formats.md, "Imported guides").
cp -r "$tmp/inverse" "$tmp/naive"
awk '/^QRest /{ next } /^Q /{ rest = $0; sub(/^Q /, "QRest ", rest); print rest; print; next } { print }' \
    "$tmp/inverse/guides.txt" > "$tmp/naive/guides.txt"
for run in inverse naive; do
    "$hk" simulate "$tmp/$run/setup.txt" --frames 61 --fps 30 --preroll 0 "${size[@]}" -o "$tmp/$run-out" --quiet
done
cp "$tmp/inverse-out/frame_0000.png" docs/images/capture-sintel-capture.png
cp "$tmp/naive-out/frame_0060.png" docs/images/capture-sintel-naive.png
# The import at 2 s is drawn from the captured floats (docs/capture.md, "Measured"): the
# same picture as the capture, which the page shows for both.
if cmp -s "$tmp/inverse-out/frame_0000.png" "$tmp/inverse-out/frame_0060.png"; then
    echo "make-capture-images.sh: the import at 2 s is the capture's picture byte for byte"
else
    cp "$tmp/inverse-out/frame_0060.png" docs/images/capture-sintel-inverse.png
    echo "make-capture-images.sh: the import at 2 s differs from the capture: docs/images/capture-sintel-inverse.png" \
        "written; docs/capture.md shows the capture's picture for it and must be changed" >&2
    exit 1
fi
