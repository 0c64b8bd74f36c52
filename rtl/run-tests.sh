#!/bin/sh
# Lints the RTL and runs every testbench in rtl/tb/; exits non-zero on any failure.
#
# Lint: verilator --lint-only -Wall on the synthesizable files with fitkit_raster as top,
# and again with the simulation top (rtl/sim/). Testbenches: Icarus (iverilog -g2012) when
# it is installed, else Verilator's --binary --timing build of the same files. Build
# products go to $RTL_BUILD (default target/rtl, beside cargo's output).
set -eu
cd "$(dirname "$0")/.."
BUILD=${RTL_BUILD:-target/rtl}
mkdir -p "$BUILD"

verilator --lint-only -Wall rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall rtl/*.v rtl/sim/*.v --top-module fitkit_sim_top
echo "lint: clean"

# testbench name, then the RTL files it needs
run() {
    tb=$1
    shift
    if command -v iverilog >/dev/null 2>&1; then
        iverilog -g2012 -I rtl/tb -s "$tb" -o "$BUILD/$tb.vvp" "rtl/tb/$tb.v" "$@"
        # vvp exits 0 after $fatal; the testbench's summary line decides.
        vvp -n "$BUILD/$tb.vvp" | tee "$BUILD/$tb.log"
    else
        verilator --binary --timing -Wno-fatal -Wno-lint -Wno-style -Irtl/tb \
            --top-module "$tb" "rtl/tb/$tb.v" "$@" -Mdir "$BUILD/$tb" -o "$tb" \
            -MAKEFLAGS "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0" >"$BUILD/$tb.build.log"
        "$BUILD/$tb/$tb" | tee "$BUILD/$tb.log"
    fi
    grep -q ", 0 failed$" "$BUILD/$tb.log"
}

run tb_spi rtl/spi_slave.v rtl/spi_decoder.v rtl/fifo36.v
run tb_fifo rtl/fifo36.v rtl/frag_fifo.v
run tb_line rtl/line_unit.v
run tb_tri rtl/tri_unit.v
run tb_top rtl/*.v rtl/sim/*.v
echo "rtl: all testbenches passed"
