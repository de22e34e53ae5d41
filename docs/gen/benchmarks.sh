#!/bin/sh
# Writes docs/benchmarks.md to stdout: the prose of benchmarks.md.in with its
# tables and figures computed from the benchmarks' CSVs in examples/gallery
# (benchmarks.awk). usage: sh docs/gen/benchmarks.sh [SOURCE_DIR]
set -eu
export LC_ALL=C
cd "${1:-.}"
awk -v data=examples/gallery -f docs/gen/benchmarks.awk docs/gen/benchmarks.md.in
