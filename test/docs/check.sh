#!/bin/sh
# A generated document is what its script makes now: docs/NAME.md against
# the output of docs/gen/NAME.sh, so that it cannot go stale.
# usage: check.sh SOURCE_DIR NAME   (fix: make docs)
set -eu
root=$1
name=$2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
sh "$root/docs/gen/$name.sh" "$root" > "$out"
if ! diff -u "$root/docs/$name.md" "$out"; then
    echo "docs/$name.md is not what docs/gen/$name.sh writes: run make docs and commit it"
    exit 1
fi
echo "docs/$name.md: as generated"
