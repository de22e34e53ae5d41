#!/usr/bin/env bash
# Bad command lines given to a demo and to a benchmark: each must be refused
# with exit status 2 and a message on stderr that names the option at fault.
#
# usage: check.sh DEMO BENCH   (build/examples/drape_table, .../bench_drape)
set -u

if [ $# -ne 2 ]; then
    echo "usage: $0 DEMO BENCH" >&2
    exit 2
fi
demo=$1 bench=$2 fails=0

# refused PROGRAM NAME ARGS...: PROGRAM ARGS exits 2 and says NAME on stderr.
refused() {
    local prog=$1 name=$2 err rc
    shift 2
    err=$("$prog" "$@" 2>&1 >/dev/null)
    rc=$?
    if [ "$rc" -ne 2 ] || [[ "$err" != *"$name"* ]]; then
        echo "FAIL: ${prog##*/} $*: exit $rc (want 2), message without '$name': $err"
        fails=$((fails + 1))
    else
        echo "ok: ${prog##*/} $*: $err"
    fi
}

refused "$demo" --no-such-flag --no-such-flag --check    # unknown
refused "$demo" --alp --alp 0.5                          # abbreviated
refused "$demo" --alpha --short --alpha                  # no value
refused "$demo" --alpha --alpha 0,1.5                    # out of range
refused "$demo" --grid --grid 162
refused "$demo" --size --size=16x16
refused "$demo" --fabric --fabric tweed
refused "$demo" stray --grid 5 stray                     # not an option

refused "$bench" --no-such-flag --no-such-flag --fast
refused "$bench" --max-wall --fast --max-wall            # no value
refused "$bench" --grid --grid 1002                      # out of range
refused "$bench" --self-collision --self-collision 2
refused "$bench" --solver --solver=nope

exit $((fails > 0))
