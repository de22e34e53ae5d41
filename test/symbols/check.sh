#!/bin/bash
# The shared libraries export exactly the functions their public headers
# mark ODECLOTH_API: none missing (declared, not defined) and no internal
# name leaked (defined and exported, not declared); and no function the
# headers name that the library defines left unmarked (so hidden). The
# installed static library defines globally only those functions too (its
# internal names are local: a user's own functions cannot clash with them),
# and every other global of the library's objects carries its internal prefix.
# usage: check.sh SHARED INTERNAL PUBLIC_STATIC PREFIX HEADER... (a library:
# shared, the build's static archive of its objects, the installed static
# library, its internal names' prefix; and the headers it implements)
set -u
lib=$1
static=$2
public=$3
prefix=$4
shift 4
if ! command -v nm >/dev/null; then
    echo "symbols: nm not found (binutils)"
    exit 1
fi
exported=$(nm -D --defined-only "$lib" | awk '$2 == "T" || $2 == "W" { print $3 }' | sort -u)
# the headers' code: no comments, no preprocessor lines
code=$(cat "$@" | perl -0pe 's{/\*.*?\*/}{}gs; s{//[^\n]*}{}g; s{^[ \t]*#[^\n]*}{}mg')
# a declaration: ODECLOTH_API, a return type, the name before its '('
declared=$(echo "$code" | tr '\n' ' ' | grep -o 'ODECLOTH_API[^;(]*(' |
    sed -E 's/.*[^A-Za-z0-9_]([A-Za-z_][A-Za-z0-9_]*)[[:space:]]*\($/\1/' | sort -u)
if [ -z "$declared" ] || [ -z "$exported" ]; then
    echo "symbols: nothing read from $lib or $*"
    exit 1
fi
missing=$(comm -13 <(echo "$exported") <(echo "$declared"))
# functions the static library defines globally whose names the headers use as calls
defined=$(nm --defined-only "$static" 2>/dev/null | awk '$2 == "T" { print $3 }' | sort -u)
named=$(echo "$code" | grep -o '[A-Za-z_][A-Za-z0-9_]*[[:space:]]*(' | sed -E 's/[[:space:]]*\($//' | sort -u)
unmarked=$(comm -12 <(echo "$defined") <(echo "$named") | comm -23 - <(echo "$declared"))
leaked=$(comm -23 <(echo "$exported") <(echo "$declared"))
# every global the installed static library defines (functions and data)
global=$(nm --defined-only --extern-only "$public" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u)
static_leaked=$(comm -23 <(echo "$global") <(echo "$declared"))
# every global the objects define, functions and data, that no header declares
internal=$(nm --defined-only --extern-only "$static" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u |
    comm -23 - <(echo "$declared"))
unprefixed=$(echo "$internal" | grep -v "^$prefix" || true)
status=0
# report MESSAGE LIST: the message and the list's lines, a failure, if the list is not empty
report() {
    if [ -n "$2" ]; then
        echo "symbols: $1"
        echo "$2" | sed 's/^/  /'
        status=1
    fi
}
if [ -z "$internal" ]; then
    echo "symbols: no internal name read from $static"
    status=1
fi
report "internal names in $(basename "$static") without the prefix $prefix:" "$unprefixed"
report "declared ODECLOTH_API in the headers but not exported by $(basename "$lib"):" "$missing"
report "named in the headers and defined in $(basename "$static") but not ODECLOTH_API (hidden):" "$unmarked"
report "exported by $(basename "$lib") but not declared ODECLOTH_API in a public header:" "$leaked"
if [ -z "$global" ]; then
    echo "symbols: nothing read from $public"
    status=1
fi
report "global in $(basename "$public") but not declared ODECLOTH_API in a public header:" "$static_leaked"
echo "symbols: $(basename "$lib"): $(echo "$exported" | wc -l) exported, $(echo "$declared" | wc -l) declared;" \
    "$(basename "$public"): $(echo "$global" | wc -l) global"
exit $status
