#!/usr/bin/env bash
# Install odecloth into a scratch prefix (BUILD_DIR/_install) and prove that
# a user can build against it both ways:
#   1. CMake: find_package(odecloth), every imported target (CONSUMER_DIR),
#   2. pkg-config: odecloth and odecloth-ode, with the rpath the README
#      tells users to add, run without LD_LIBRARY_PATH,
#   3. a program linked to the plugin alone, run without LD_LIBRARY_PATH.
#
# usage: check.sh CMAKE BUILD_DIR CONSUMER_DIR CC PKG_CONFIG
# environment: ODECLOTH_CFLAGS  C flags of the build (sanitizers must match)
#              ODECLOTH_CONFIG  build configuration, may be empty
set -euo pipefail

if [ $# -ne 5 ]; then
    echo "usage: $0 CMAKE BUILD_DIR CONSUMER_DIR CC PKG_CONFIG" >&2
    exit 2
fi
cmake=$1 build=$2 src=$3 cc=$4 pkgconfig=$5
cflags=${ODECLOTH_CFLAGS:-}
config=${ODECLOTH_CONFIG:-}

prefix=$build/_install
work=$build/_consumer
rm -rf "$prefix" "$work"
mkdir -p "$work"

echo "== install into $prefix"
"$cmake" --install "$build" --prefix "$prefix" ${config:+--config "$config"}

echo "== CMake consumer (find_package)"
"$cmake" -S "$src" -B "$work/cmake" \
    -DCMAKE_C_COMPILER="$cc" -DCMAKE_C_FLAGS="$cflags" \
    -DCMAKE_PREFIX_PATH="$prefix" -DEXPECTED_PREFIX="$prefix"
"$cmake" --build "$work/cmake"
for exe in consumer consumer_static consumer_ode consumer_ode_static; do
    echo "-- $exe"
    "$work/cmake/$exe"
done

echo "== pkg-config consumer"
pc=$(find "$prefix" -name odecloth.pc -print -quit)
if [ -z "$pc" ]; then
    echo "odecloth.pc was not installed" >&2
    exit 1
fi
# Ahead of the system's own pkg-config directories (ODE and libccd are there).
export PKG_CONFIG_PATH=$(dirname "$pc")${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
libdir=$("$pkgconfig" --variable=libdir odecloth)

# As README.md says: the .pc files carry no rpath, the user adds libdir's.
# shellcheck disable=SC2086 # flags are word lists
"$cc" $cflags -Wall -Wextra -Werror -o "$work/pc_consumer" "$src/consumer.c" \
    $("$pkgconfig" --cflags --libs odecloth) \
    -Wl,-rpath,"$("$pkgconfig" --variable=libdir odecloth)"
# shellcheck disable=SC2086
"$cc" $cflags -Wall -Wextra -Werror -o "$work/pc_consumer_ode" "$src/consumer_ode.c" \
    $("$pkgconfig" --cflags --libs odecloth-ode) \
    -Wl,-rpath,"$("$pkgconfig" --variable=libdir odecloth-ode)"
for exe in pc_consumer pc_consumer_ode; do
    echo "-- $exe"
    env -u LD_LIBRARY_PATH "$work/$exe"
done

echo "== the plugin alone, no LD_LIBRARY_PATH (its RUNPATH finds the core)"
# shellcheck disable=SC2086
"$cc" $cflags -Wall -Wextra -Werror -o "$work/plugin_only" "$src/consumer_plugin_only.c" \
    -I"$("$pkgconfig" --variable=includedir odecloth)" $("$pkgconfig" --cflags ode) \
    -L"$libdir" -lodecloth_ode $("$pkgconfig" --libs ode) -Wl,-rpath,"$libdir"
env -u LD_LIBRARY_PATH "$work/plugin_only"

echo "install_package: ok"
