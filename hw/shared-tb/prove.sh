# prove.sh -- the formal step of the blocks' run-tests.sh, sourced (POSIX sh): the
# properties beside a module (`ifdef FORMAL`) proved by Yosys's own SAT solver from a
# reset in the first step: a bounded check and temporal induction up to 24 steps, on
# small instances (the properties do not depend on the width, nor on the depth but
# through its bit count). yosys-smtbmc with Debian's z3 4.8 stalls in step 0 on the
# ray-tracing core's bus adapter, so one method serves every block.
#
# prove NAME TOP "FILES" [chparam arguments...]
#   NAME names the log ($BUILD/NAME.formal.log) and, when a property fails, the
#   counterexample waveform ($BUILD/NAME.formal.vcd), which the failure message names.
#   Exits the script on failure. PROVE_SECONDS sums the time of every proof.
# prove_fails NAME TOP "FILES" [chparam arguments...]
#   the same on a deliberately broken copy: succeeds only if the proof fails and leaves
#   its waveform, so a proof that could not fail is caught.
# Needs $BUILD (an absolute folder) and -Irtl to find the blocks' headers.
PROVE_SECONDS=0

prove_run() {
    name=$1
    top=$2
    files=$3
    shift 3
    rm -f "$BUILD/$name.formal.vcd"
    t0=$(date +%s)
    yosys -p "read_verilog -formal -DFORMAL -Irtl $files; chparam $* $top; \
        prep -top $top; flatten; memory_map; opt -fast; async2sync; dffunmap; \
        sat -tempinduct -prove-asserts -set-assumes -set-at 1 rst 1 -maxsteps 24 \
        -dump_vcd $BUILD/$name.formal.vcd" >"$BUILD/$name.formal.log" 2>&1 || true
    PROVE_SECONDS=$((PROVE_SECONDS + $(date +%s) - t0))
    grep -q "Induction step proven: SUCCESS" "$BUILD/$name.formal.log"
}

prove() {
    name=$1
    if ! prove_run "$@"; then
        grep -E "FAIL|ERROR" "$BUILD/$name.formal.log" | head -5
        echo "formal: $name NOT proved (log: $BUILD/$name.formal.log, counterexample:" \
            "$BUILD/$name.formal.vcd)"
        exit 1
    fi
    echo "formal: $name proved (induction)"
}

prove_fails() {
    name=$1
    if prove_run "$@"; then
        echo "formal: the broken $name was proved: the properties cannot fail"
        exit 1
    fi
    if [ ! -s "$BUILD/$name.formal.vcd" ]; then
        echo "formal: the broken $name failed without a counterexample waveform"
        exit 1
    fi
    echo "formal: the broken $name fails, counterexample $BUILD/$name.formal.vcd"
}
