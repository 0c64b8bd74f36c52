# tb.sh -- the testbench step of the blocks' run-tests.sh, sourced (POSIX sh): a
# self-checking testbench compiled and run under Icarus (iverilog -g2012) or Verilator
# (--binary --timing), and on failure run once more writing a waveform the failure names.
#
# run TB NAME PARAM FILES...
#   compiles tb/TB.v (module TB) with FILES into $BUILD/NAME*, runs it into
#   $BUILD/NAME.log and prints the log. PARAM is -, NAME=VALUE[,NAME=VALUE...] (parameters
#   of the testbench overridden), or a bare VALUE for the testbench's LANES. The testbench
#   passes only when the simulator exits 0 and its summary line ends ", 0 failed"
#   (check.vh's bookkeeping): Icarus 11's vvp exits 1 after $fatal and a Verilated bench
#   aborts, but a bench that ends with $finish whatever it found leaves the summary to
#   decide. A failing bench is run again with +vcd=$BUILD/NAME.vcd (check.vh dumps every
#   signal to it; under Verilator the bench is first rebuilt with --trace, into
#   $BUILD/NAME-trace, so a passing run pays nothing for it), then one line names the log
#   and the waveform, and the script exits.
# run_fails TB NAME PARAM FILES...
#   the same on a deliberately broken copy: succeeds only if the bench fails and its
#   failure line names a waveform that holds a VCD header, so the mechanism cannot rot.
# Needs $BUILD (an absolute folder), $SIM (iverilog or verilator) and the block's tb/ and
# rtl/ beside the caller; ../shared-tb (this folder, for check.vh) is on the include path.

# tb_compile TB NAME PARAM TRACE FILES...: the bench's binary for $SIM (TRACE: yes or no).
tb_compile() {
    tb=$1
    name=$2
    param=$3
    trace=$4
    shift 4
    case $param in
    -) ;;
    *=*) ;;
    *) param=LANES=$param ;;
    esac
    if [ "$SIM" = iverilog ]; then
        if [ "$param" != - ]; then
            for p in $(echo "$param" | tr ',' ' '); do set -- -P "$tb.$p" "$@"; done
        fi
        iverilog -g2012 -I tb -I ../shared-tb -I rtl -s "$tb" -o "$BUILD/$name.vvp" \
            "tb/$tb.v" "$@"
    else
        if [ "$param" != - ]; then
            for p in $(echo "$param" | tr ',' ' '); do set -- -G"$p" "$@"; done
        fi
        mdir=$BUILD/$name
        [ "$trace" = no ] || { set -- --trace "$@"; mdir=$BUILD/$name-trace; }
        verilator --binary --timing -Wno-fatal -Wno-lint -Wno-style -Itb -I../shared-tb -Irtl \
            --top-module "$tb" "tb/$tb.v" "$@" -Mdir "$mdir" -o "$tb" \
            -MAKEFLAGS "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0" >"$mdir.build.log" 2>&1 || {
            echo "verilator could not build $tb (log: $mdir.build.log)"
            return 1
        }
    fi
}

# tb_sim TB NAME TRACE [plusargs...]: runs the compiled bench; its exit status.
tb_sim() {
    tb=$1
    name=$2
    trace=$3
    shift 3
    if [ "$SIM" = iverilog ]; then
        vvp -n "$BUILD/$name.vvp" "$@"
    elif [ "$trace" = no ]; then
        "$BUILD/$name/$tb" "$@"
    else
        "$BUILD/$name-trace/$tb" "$@"
    fi
}

run() {
    tb=$1
    name=$2
    tb_compile "$tb" "$name" no "$3" no 2>/dev/null || true
    return 0
}

run() {
    tb_try "$@" || exit 1
}

run_fails() {
    if out=$(tb_try "$@"); then
        printf '%s\n' "$out"
        echo "testbench: the broken $2 passed: the bench cannot fail"
        exit 1
    fi
    wave=$(printf '%s\n' "$out" | sed -n 's/^FAIL: testbench .*, waveform: \(.*\)$/\1/p')
    # its failure line, reworded: a log searched for "FAIL" finds real failures only
    printf '%s\n' "$out" | sed -n 's/^FAIL: testbench \(.*\)$/as meant: testbench \1/p'
    if [ -z "$wave" ] || [ ! -s "$wave" ] || ! grep -q '\$enddefinitions' "$wave"; then
        echo "testbench: the broken $2 failed without a waveform"
        exit 1
    fi
    echo "testbench: the broken $2 fails, waveform $wave"
}

# tb_try TB NAME PARAM FILES...: `run`'s work; non-zero after printing the failure line.
tb_try() {
    tb=$1
    name=$2
    param=$3
    shift 3
    tb_compile "$tb" "$name" "$param" no "$@" || return 1
    if tb_sim "$tb" "$name" no >"$BUILD/$name.log" 2>&1; then status=0; else status=$?; fi
    cat "$BUILD/$name.log"
    if [ "$status" = 0 ] && grep -q ", 0 failed$" "$BUILD/$name.log"; then
        return 0
    fi
    wave=$BUILD/$name.vcd
    rm -f "$wave"
    if [ "$SIM" = iverilog ] || tb_compile "$tb" "$name" "$param" yes "$@"; then
        tb_sim "$tb" "$name" yes +vcd="$wave" >"$BUILD/$name.wave.log" 2>&1 || true
    fi
    if [ -s "$wave" ]; then
        where="waveform: $wave"
    else
        where="no waveform (the bench includes no check.vh? see $BUILD/$name.wave.log)"
    fi
    echo "FAIL: testbench $tb ($name) failed; log: $BUILD/$name.log, $where"
    return 1
}
