#!/bin/sh
# Writes docs/api.md to stdout: the hand-written introduction (api.head.md),
# then, header by header, every public function's declaration with the
# comment above it (api.awk). usage: sh docs/gen/api.sh [SOURCE_DIR]
set -eu
root=${1:-.}
cd "$root"
cat docs/gen/api.head.md
for h in core/include/odecloth/cloth.h core/include/odecloth/fabric.h \
         core/include/odecloth/selfcollision.h plugin/include/odecloth/dcloth.h; do
    echo
    awk -v path="$h" -f docs/gen/api.awk "$h"
done
