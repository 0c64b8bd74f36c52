#!/bin/sh
# Lints the ray-casting core's RTL and runs its testbenches; exits non-zero on any
# failure.
#
# Lint: verilator --lint-only -Wall on the synthesisable files (rtl/) with each unit as
# top, with the simulation top (sim/) and with the place-and-route wrapper (synth/).
# Testbenches: Icarus (iverilog -g2012) when it is installed, else Verilator's --binary
# --timing build (RTL_SIM=iverilog or RTL_SIM=verilator forces one; ../shared-tb/tb.sh: a
# failing bench is run again into a waveform its failure line names, and a broken divider
# must fail that way). Paths below are relative to this block's folder; build products go
# to $RTL_BUILD (default target/rtl at the workspace root; a relative $RTL_BUILD is taken
# from the workspace root). The differential tests against the golden
# model are the bridge crate's (rtl-sim/, cargo test -p rt-core-rtl-sim).
set -eu
cd "$(dirname "$0")/../.."
BUILD=${RTL_BUILD:-target/rtl}
mkdir -p "$BUILD"
BUILD=$(cd "$BUILD" && pwd)
cd hw/rt-core
SIM=${RTL_SIM:-auto}
if [ "$SIM" = auto ]; then
    if command -v iverilog >/dev/null 2>&1; then SIM=iverilog; else SIM=verilator; fi
fi

for top in q16_dot q16_div q16_sqrt q16_rsqrt q16_norm3 q16_powi udiv_pipe usqrt_pipe dly \
    isect_quadric isect_flat isect_cube rt_isect rt_raygen rt_xform rt_normal rt_light \
    rt_shade rt_fifo rt_axil rt_regs rt_readback rt_cast rt_device q16_to_f32; do
    verilator --lint-only -Wall -Irtl rtl/*.v --top-module "$top"
done
# the intersection unit with one shape family, one shape, and none of the quadrics
for shapes in 0000001 0010000 0100000 0001110 1000000 1001110; do
    verilator --lint-only -Wall -Irtl rtl/*.v --top-module rt_isect -GSHAPES="7'b$shapes"
done
# the colour with several lanes; the frame core with one object and with spheres and
# planes only
verilator --lint-only -Wall -Irtl rtl/*.v --top-module rt_shade -GLIGHTS=3
verilator --lint-only -Wall -Irtl rtl/*.v --top-module rt_cast -GOBJ=1
verilator --lint-only -Wall -Irtl rtl/*.v --top-module rt_cast -GSHADOWS=0
verilator --lint-only -Wall -Irtl rtl/*.v --top-module rt_cast -GSHAPES="7'b0000011" -GOBJ=5
verilator --lint-only -Wall -Irtl rtl/*.v sim/*.v --top-module rt_math_top
# the pin wrappers `cargo xtask synth` places (synth/)
for top in rt_device_pins rt_isect_pins; do
    verilator --lint-only -Wall -Irtl rtl/*.v synth/*.v ../shared-synth/*.v --top-module "$top"
done
echo "lint: clean"
# formal: the properties beside a module (ifdef FORMAL), proved at small sizes
# (../shared-tb/prove.sh: Yosys's own SAT solver, a failing proof names its waveform)
. ../shared-tb/prove.sh
prove rt_fifo_w4 rt_fifo 'rtl/*.v' -set W 4 -set AW 2
prove rt_fifo_w3 rt_fifo 'rtl/*.v' -set W 3 -set AW 1
prove rt_axil rt_axil 'rtl/*.v' -set AW 4
prove rt_readback rt_readback 'rtl/*.v'
echo "formal: done in $PROVE_SECONDS s"
# Icarus reads the whole core too (its testbench below covers the arithmetic units; the
# intersection unit's and the frame's differential tests run under Verilator, in rtl-sim/)
if [ "$SIM" = iverilog ]; then
    iverilog -g2012 -Irtl -s rt_cast -o "$BUILD/rt_cast.vvp" rtl/*.v
    iverilog -g2012 -Irtl -s rt_device -o "$BUILD/rt_device.vvp" rtl/*.v
    echo "icarus: rt_cast and rt_device elaborate"
fi

# testbenches (../shared-tb/tb.sh): testbench, build name, a parameter (or -), then the
# files it needs; a failing bench is rerun into a waveform the failure line names
. ../shared-tb/tb.sh
run tb_units rt_tb_units - rtl/*.v sim/rt_math_top.v
# a divider that sets every quotient's last bit must fail tb_units (200 operand sets),
# naming its waveform
mkdir -p "$BUILD/rt_div_broken"
cp rtl/*.v "$BUILD/rt_div_broken/"
sed "s/y <= u1\[2\] ? 32'd0 - q1 : q1;/y <= (u1[2] ? 32'd0 - q1 : q1) | 32'd1;/" rtl/q16_div.v \
    >"$BUILD/rt_div_broken/q16_div.v"
if cmp -s rtl/q16_div.v "$BUILD/rt_div_broken/q16_div.v"; then
    echo "testbench: the breakage did not apply to rtl/q16_div.v"
    exit 1
fi
run_fails tb_units rt_tb_units_broken N=200 "$BUILD"/rt_div_broken/*.v sim/rt_math_top.v
echo "rt-core: all testbenches passed"
