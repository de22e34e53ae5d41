#!/bin/sh
# Writes docs/api.md to stdout: the hand-written introduction (api.head.md),
# then, header by header, every public function's declaration with the
# comment above it (api.awk). usage: sh docs/gen/api.sh [SOURCE_DIR]
set -eu
export LC_ALL=C
root=${1:-.}
cd "$root"
cat docs/gen/api.head.md
# every public header that declares functions (export.h only defines the mark)
for h in core/include/odecloth/*.h plugin/include/odecloth/*.h; do
    grep -q '^ODECLOTH_API' "$h" || continue
    echo
    awk -v path="$h" -f docs/gen/api.awk "$h"
done
