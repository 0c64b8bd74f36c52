#!/bin/sh
# Builds tb_fpgfx.v with Verilator (--binary --timing) against the RTL in RTL_DIR (every
# RTL_DIR/*.v, top module fitkit_raster)
# and runs it on the vectors beside this script.
# Exits 0 only when the testbench's summary says every check passed. Written by fpgfx
# @VERSION@ (`fpgfx vectors raster`); docs/vectors.md describes the vectors and the checks.
#
# RTL_DIR is also the include path, for the headers its modules include (the FITkit
# block's fitkit_map.vh).
# Usage: sh run-verilator.sh RTL_DIR [+plusarg ...]   (plusargs: see tb_fpgfx.v)
# Build products and the logs go to build-verilator/ beside this script. Verilator needs
# make and a C++ compiler as well.
set -u
me=run-verilator.sh
if [ $# -lt 1 ]; then
    echo "usage: sh $me RTL_DIR [+plusarg ...]" >&2
    exit 2
fi
for tool in verilator make; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "$me: $tool not found: run cargo xtask setup (installs Verilator), or install verilator" >&2
        exit 127
    fi
done
if ! rtl=$(cd "$1" 2>/dev/null && pwd); then
    echo "$me: RTL_DIR $1 is not a directory" >&2
    exit 2
fi
shift
for v in "$rtl"/*.v; do
    if [ ! -f "$v" ]; then
        echo "$me: no .v files in $rtl" >&2
        exit 2
    fi
done
here=$(cd "$(dirname "$0")" && pwd)
build="$here/build-verilator"
mkdir -p "$build" || exit 1
cd "$here" || exit 1

# Unoptimised C++: the build dominates a run of this size.
if ! verilator --binary --timing -Wno-fatal -Wno-lint -Wno-style \
    -I"$rtl" --top-module tb_fpgfx tb_fpgfx.v "$rtl"/*.v -Mdir "$build" -o tb_fpgfx \
    -MAKEFLAGS "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0" >"$build/build.log" 2>&1; then
    tail -n 40 "$build/build.log" >&2
    echo "$me: verilator could not build tb_fpgfx.v with $rtl/*.v (log: $build/build.log)" >&2
    exit 1
fi
"$build/tb_fpgfx" "$@" >"$build/tb_fpgfx.log" 2>&1
status=$?
cat "$build/tb_fpgfx.log"
if ! grep -q '^TB_FPGFX ' "$build/tb_fpgfx.log"; then
    echo "$me: the simulation ended without a summary (exit status $status)" >&2
    exit 1
fi
grep -q '^tb_fpgfx: [0-9]* passed, 0 failed$' "$build/tb_fpgfx.log" \
    && grep -q '^TB_FPGFX PASS$' "$build/tb_fpgfx.log"
