#!/bin/sh
# Builds tb_fpgfx.v with Icarus Verilog against the RTL in RTL_DIR (every RTL_DIR/*.v,
# top module fitkit_raster)
# and runs it on the vectors beside this script. Exits 0 only
# when the testbench's summary says every check passed. Written by fpgfx @VERSION@
# (`fpgfx vectors raster`); docs/vectors.md describes the vectors and the checks.
#
# RTL_DIR is also the include path, for the headers its modules include (the FITkit
# block's fitkit_map.vh).
# Usage: sh run-iverilog.sh RTL_DIR [+plusarg ...]   (plusargs: see tb_fpgfx.v)
# Build products and the log go to build-iverilog/ beside this script.
set -u
me=run-iverilog.sh
if [ $# -lt 1 ]; then
    echo "usage: sh $me RTL_DIR [+plusarg ...]" >&2
    exit 2
fi
for tool in iverilog vvp; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "$me: $tool not found: run cargo xtask setup (installs Icarus Verilog), or install iverilog" >&2
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
build="$here/build-iverilog"
mkdir -p "$build" || exit 1
cd "$here" || exit 1

if ! iverilog -g2012 -I "$rtl" -s tb_fpgfx -o "$build/tb_fpgfx.vvp" tb_fpgfx.v "$rtl"/*.v \
    >"$build/compile.log" 2>&1; then
    cat "$build/compile.log" >&2
    echo "$me: iverilog could not compile tb_fpgfx.v with $rtl/*.v (log: $build/compile.log)" >&2
    exit 1
fi
vvp -n "$build/tb_fpgfx.vvp" "$@" >"$build/tb_fpgfx.log" 2>&1
status=$?
cat "$build/tb_fpgfx.log"
if ! grep -q '^TB_FPGFX ' "$build/tb_fpgfx.log"; then
    echo "$me: the simulation ended without a summary (vvp exit status $status)" >&2
    exit 1
fi
grep -q '^tb_fpgfx: [0-9]* passed, 0 failed$' "$build/tb_fpgfx.log" \
    && grep -q '^TB_FPGFX PASS$' "$build/tb_fpgfx.log"
