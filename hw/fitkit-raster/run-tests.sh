#!/bin/sh
# Lints the FITkit raster block's RTL and runs every testbench in tb/; exits non-zero on
# any failure.
#
# Lint: verilator --lint-only -Wall on the synthesizable files (rtl/) with fitkit_raster as
# top, and again with the simulation top (sim/). Testbenches: Icarus (iverilog -g2012) when
# it is installed, else Verilator's --binary --timing build of the same files
# (RTL_SIM=iverilog or RTL_SIM=verilator forces one; ../shared-tb/tb.sh: a failing bench
# is run again into a waveform its failure line names, and a broken copy of the SPI slave
# must fail that way). Paths below are relative to this
# block's folder; build products go to $RTL_BUILD (default target/rtl at the workspace
# root, beside cargo's output; a relative $RTL_BUILD is taken from the workspace root).
# Every compile gets -I rtl: the modules and testbenches include the generated map header
# rtl/fitkit_map.vh. Formal: the properties beside the FIFOs (`ifdef FORMAL`), proved
# with ../shared-tb/prove.sh; a failing proof names its counterexample waveform.
set -eu
cd "$(dirname "$0")/../.."
BUILD=${RTL_BUILD:-target/rtl}
mkdir -p "$BUILD"
BUILD=$(cd "$BUILD" && pwd)
cd hw/fitkit-raster
SIM=${RTL_SIM:-auto}
if [ "$SIM" = auto ]; then
    if command -v iverilog >/dev/null 2>&1; then SIM=iverilog; else SIM=verilator; fi
fi

verilator --lint-only -Wall -Irtl rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall -Irtl rtl/*.v sim/*.v --top-module fitkit_sim_top
# the cocotb testbench's top (its clock is Icarus-only, the rest is linted)
verilator --lint-only -Wall -Irtl rtl/*.v sim/*.v --top-module fitkit_cocotb_top
verilator --lint-only -Wall -Irtl -GTRI_LANES=8 rtl/*.v --top-module fitkit_raster
# the line-only and triangle-only builds for the seed's XC3S50, and their sim tops
verilator --lint-only -Wall -Irtl -GTRI_UNIT=0 rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall -Irtl -GLINE_UNIT=0 rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall -Irtl -GLINE_UNIT=0 -GTRI_SMALL=1 rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall -Irtl -GTRI_SMALL=1 rtl/*.v --top-module fitkit_raster
verilator --lint-only -Wall -Irtl -GTRI_UNIT=0 rtl/*.v sim/*.v --top-module fitkit_sim_top
verilator --lint-only -Wall -Irtl -GLINE_UNIT=0 -GTRI_SMALL=1 rtl/*.v sim/*.v \
    --top-module fitkit_sim_top
# a parameter outside what the block builds stops the build, naming the rule
for bad in -GTRI_LANES=3 -GTRI_UNIT=2 "-GLINE_UNIT=0 -GTRI_UNIT=0" "-GTRI_SMALL=1 -GTRI_LANES=8"; do
    # shellcheck disable=SC2086 # $bad is one or two -G options
    if verilator --lint-only -Wall -Irtl $bad rtl/*.v --top-module fitkit_raster \
        >"$BUILD/lint-bad-parameter.log" 2>&1; then
        echo "lint: $bad was accepted"
        exit 1
    fi
    if ! grep -q "_must_be_\|_are_0_or_1_" "$BUILD/lint-bad-parameter.log"; then
        echo "lint: $bad failed without naming the rule: see $BUILD/lint-bad-parameter.log"
        exit 1
    fi
done
# the pin wrapper `cargo xtask synth` places on the Gowin part (synth/)
verilator --lint-only -Wall -Irtl rtl/*.v synth/*.v ../shared-synth/*.v --top-module fitkit_raster_pins
echo "lint: clean"

# formal: the properties beside the FIFOs (proved at two depths each), the SPI slave, the
# address decoder (also without a line or a triangle unit: nothing of an absent unit's
# address reaches the FIFO), the read-back stream and the kept error (../shared-tb/prove.sh)
. ../shared-tb/prove.sh
prove fitkit_fifo36_d4 fifo36 rtl/fifo36.v -set DEPTH 4
prove fitkit_fifo36_d8 fifo36 rtl/fifo36.v -set DEPTH 8
prove fitkit_frag_fifo_a2 frag_fifo rtl/frag_fifo.v -set AW 2 -set W 4
prove fitkit_frag_fifo_a3 frag_fifo rtl/frag_fifo.v -set AW 3 -set W 4
prove fitkit_spi_slave spi_slave rtl/spi_slave.v
prove fitkit_spi_decoder spi_decoder rtl/spi_decoder.v
prove fitkit_spi_decoder_line spi_decoder rtl/spi_decoder.v -set TRI_UNIT 0
prove fitkit_spi_decoder_tri spi_decoder rtl/spi_decoder.v -set LINE_UNIT 0
prove fitkit_readback readback rtl/readback.v
prove fitkit_status status rtl/status.v
prove fitkit_cmd_exec cmd_exec rtl/cmd_exec.v
# a FIFO whose COMMIT shows one record too many must fail, with its waveform
sed 's/if (COMMIT) wr_commit <= wr_ptr;/if (COMMIT) wr_commit <= wr_ptr + 1'"'"'b1;/' \
    rtl/fifo36.v >"$BUILD/fifo36_broken.v"
if cmp -s rtl/fifo36.v "$BUILD/fifo36_broken.v"; then
    echo "formal: the breakage did not apply to rtl/fifo36.v"
    exit 1
fi
prove_fails fitkit_fifo36_broken fifo36 "$BUILD/fifo36_broken.v" -set DEPTH 4
# and one whose room flip-flop stays set when the last free record is written
sed "s/                room_r    <= ~tent_last;/                room_r    <= 1'b1;/" \
    rtl/fifo36.v >"$BUILD/fifo36_room_broken.v"
if cmp -s rtl/fifo36.v "$BUILD/fifo36_room_broken.v"; then
    echo "formal: the breakage did not apply to rtl/fifo36.v"
    exit 1
fi
prove_fails fitkit_fifo36_room_broken fifo36 "$BUILD/fifo36_room_broken.v" -set DEPTH 4
# and the slave with the CS_n synchroniser reset to high (the bug that took a reset
# mid-transaction for a new CS_n fall) must fail its reset property
sed "s/cs_s   <= 3'b000;/cs_s   <= 3'b111;/" rtl/spi_slave.v >"$BUILD/spi_slave_broken.v"
if cmp -s rtl/spi_slave.v "$BUILD/spi_slave_broken.v"; then
    echo "formal: the breakage did not apply to rtl/spi_slave.v"
    exit 1
fi
prove_fails fitkit_spi_slave_broken spi_slave "$BUILD/spi_slave_broken.v"
# and a decoder that commits a packet one of whose records found the FIFO full
sed 's/if (!len_ok | (is_rec \& (!pad_ok | !cb_ok | ovr))) begin/if (!len_ok | (is_rec \& (!pad_ok | !cb_ok))) begin/' \
    rtl/spi_decoder.v >"$BUILD/spi_decoder_broken.v"
if cmp -s rtl/spi_decoder.v "$BUILD/spi_decoder_broken.v"; then
    echo "formal: the breakage did not apply to rtl/spi_decoder.v"
    exit 1
fi
prove_fails fitkit_spi_decoder_broken spi_decoder "$BUILD/spi_decoder_broken.v"
# and a triangle-only decoder that still takes line packets into the FIFO
sed 's/& ~((LINE_UNIT == 0) & (a == `FITKIT_ADDR_LINE))/\& ~((1 == 0) \& (a == `FITKIT_ADDR_LINE))/' \
    rtl/spi_decoder.v >"$BUILD/spi_decoder_no_line_broken.v"
if cmp -s rtl/spi_decoder.v "$BUILD/spi_decoder_no_line_broken.v"; then
    echo "formal: the breakage did not apply to rtl/spi_decoder.v"
    exit 1
fi
prove_fails fitkit_spi_decoder_no_line_broken spi_decoder "$BUILD/spi_decoder_no_line_broken.v" \
    -set LINE_UNIT 0
# and the read-back that sent a late byte in the next slot (the bug that shifted the stream)
sed 's/    wire push   = arrive \& none_owed;/    wire push   = arrive;/' \
    rtl/readback.v >"$BUILD/readback_broken.v"
if cmp -s rtl/readback.v "$BUILD/readback_broken.v"; then
    echo "formal: the breakage did not apply to rtl/readback.v"
    exit 1
fi
prove_fails fitkit_readback_broken readback "$BUILD/readback_broken.v"
# and an executor whose pop flag stays set when a one-record packet leaves IDLE
sed 's/                    popping <= two;/                    popping <= 1'"'"'b1;/' \
    rtl/cmd_exec.v >"$BUILD/cmd_exec_broken.v"
if cmp -s rtl/cmd_exec.v "$BUILD/cmd_exec_broken.v"; then
    echo "formal: the breakage did not apply to rtl/cmd_exec.v"
    exit 1
fi
prove_fails fitkit_cmd_exec_broken cmd_exec "$BUILD/cmd_exec_broken.v"
# the triangle set-up's serial multiplier: the product after its last bit, at two shapes,
# and one that forgets the +1 of the sign bit's negation must fail
prove fitkit_mul_seq_a4b5 mul_seq rtl/mul_seq.v -set AW 4 -set BW 5
prove fitkit_mul_seq_a5b4 mul_seq rtl/mul_seq.v -set AW 5 -set BW 4
sed 's/                             + {{(AW+1){1'"'"'b0}}, lo\[0\] \& neg};/;/' \
    rtl/mul_seq.v >"$BUILD/mul_seq_broken.v"
if cmp -s rtl/mul_seq.v "$BUILD/mul_seq_broken.v"; then
    echo "formal: the breakage did not apply to rtl/mul_seq.v"
    exit 1
fi
prove_fails fitkit_mul_seq_broken mul_seq "$BUILD/mul_seq_broken.v" -set AW 4 -set BW 5
echo "formal: done in $PROVE_SECONDS s"

# testbenches (../shared-tb/tb.sh): testbench, build name, LANES parameter of tb_tri (or
# -), then the RTL files it needs; a failing bench is rerun into a waveform the failure
# line names
. ../shared-tb/tb.sh
run tb_spi tb_spi - rtl/spi_slave.v rtl/spi_decoder.v rtl/fifo36.v
run tb_fifo tb_fifo - rtl/fifo36.v rtl/frag_fifo.v
run tb_line tb_line - rtl/line_unit.v
run tb_tri tb_tri - rtl/tri_unit.v rtl/tri_lane.v rtl/mul_seq.v
echo "tb_tri with LANES = 8:"
run tb_tri tb_tri8 8 rtl/tri_unit.v rtl/tri_lane.v rtl/mul_seq.v
echo "tb_tri on tri_small:"
run tb_tri tb_tri_small SMALL=1 rtl/tri_small.v rtl/tri_unit.v rtl/tri_lane.v rtl/mul_seq.v
run tb_cmd_exec tb_cmd_exec - rtl/cmd_exec.v
run tb_clear tb_clear - rtl/clear_unit.v
run tb_fb_writer tb_fb_writer - rtl/fb_writer.v
run tb_readback tb_readback - rtl/readback.v rtl/spi_slave.v
run tb_status tb_status - rtl/status.v
run tb_top tb_top - rtl/*.v sim/*.v

# tb_top's file mode on a small transaction list: the RAM dump must hold the whole frame.
if [ "$SIM" = iverilog ]; then
    vvp -n "$BUILD/tb_top.vvp" +tx=tb/smoke.hex +dump="$BUILD/smoke-frame.hex" >/dev/null
else
    "$BUILD/tb_top/tb_top" +tx=tb/smoke.hex +dump="$BUILD/smoke-frame.hex" >/dev/null
fi
test "$(grep -cv '^//' "$BUILD/smoke-frame.hex")" -eq 262144
echo "tb_top file mode: frame dumped"

# a slave that takes every byte's last bit as 0 must fail tb_spi, naming its waveform
sed 's/rx_byte  <= {rx_sh, mosi_s\[1\]};/rx_byte  <= {rx_sh, 1'"'"'b0};/' \
    rtl/spi_slave.v >"$BUILD/spi_slave_tb_broken.v"
if cmp -s rtl/spi_slave.v "$BUILD/spi_slave_tb_broken.v"; then
    echo "testbench: the breakage did not apply to rtl/spi_slave.v"
    exit 1
fi
run_fails tb_spi tb_spi_broken - "$BUILD/spi_slave_tb_broken.v" rtl/spi_decoder.v rtl/fifo36.v
# and the triangle unit with the broken multiplier (above) must fail tb_tri
run_fails tb_tri tb_tri_mul_broken QUICK=1 rtl/tri_unit.v rtl/tri_lane.v "$BUILD/mul_seq_broken.v"
# and tri_small with the top-left rule of its sloped edges inverted
sed 's/ : (~ey\[9\] ^ rev);/ : (ey[9] ^ rev);/' rtl/tri_small.v >"$BUILD/tri_small_broken.v"
if cmp -s rtl/tri_small.v "$BUILD/tri_small_broken.v"; then
    echo "testbench: the breakage did not apply to rtl/tri_small.v"
    exit 1
fi
run_fails tb_tri tb_tri_small_broken SMALL=1,QUICK=1 "$BUILD/tri_small_broken.v" rtl/tri_unit.v \
    rtl/tri_lane.v rtl/mul_seq.v
echo "rtl: all testbenches passed"
