#!/bin/bash
# Lists every C function body longer than LIMIT lines (default 150) in the
# sources under core/, plugin/, examples/ and test/, as "file:line name length",
# and fails when there is one. A body runs from its "{" line to its "}" line.
# usage: function_length.sh SOURCE_DIR [LIMIT]
set -u
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "function_length: usage: function_length.sh SOURCE_DIR [LIMIT]"
    exit 1
fi
limit=${2:-150}
cd "$1" || exit 1
mapfile -t files < <(find core plugin examples test -name '*.[ch]' | sort)
if [ ${#files[@]} -eq 0 ]; then
    echo "function_length: no C sources under $1"
    exit 1
fi
# clang-format (Linux braces) puts a function's "{" (maybe with a comment) and "}" alone at column 0;
# the signature is the run of lines above the "{" since a blank, "#", ";" or "}" line
awk -v limit="$limit" '
FNR == 1 { nsig = 0; start = 0; nfiles++ }
start == 0 && /^\{[[:space:]]*(\/[*\/].*)?$/ {
    start = FNR
    sig = ""
    for (k = 1; k <= nsig; k++) sig = sig " " siglines[k]
    name = sig
    sub(/\(.*$/, "", name)
    sub(/^.*[^A-Za-z0-9_]/, "", name)
    at = FNR - nsig
    next
}
start > 0 && /^\}/ {
    length_ = FNR - start + 1
    if (length_ > limit) {
        printf "%s:%d %s %d\n", FILENAME, at, name, length_
        nlong++
    }
    start = 0
    nsig = 0
    next
}
start == 0 {
    if ($0 ~ /^[[:space:]]*$/ || $0 ~ /^#/ || $0 ~ /;[[:space:]]*$/ || $0 ~ /^\}/ || $0 ~ /\*\/[[:space:]]*$/) nsig = 0
    else siglines[++nsig] = $0
}
END {
    if (nlong > 0) {
        printf "function_length: %d function(s) longer than %d lines\n", nlong, limit
        exit 1
    }
    printf "function_length: no function longer than %d lines in %d files\n", limit, nfiles
}
' "${files[@]}"
