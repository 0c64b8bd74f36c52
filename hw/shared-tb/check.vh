// The pass/fail bookkeeping of a self-checking testbench: `check(ok, what)` counts a
// check and prints `FAIL: what` when it does not hold. Included inside a module.
integer passed = 0, failed = 0;
task check(input ok, input [8*48-1:0] what);
    begin
        if (ok) passed = passed + 1;
        else begin
            failed = failed + 1;
            $display("FAIL: %0s", what);
        end
    end
endtask

// The waveform of a failing run: with +vcd=PATH (tb.sh's second run of a failing bench)
// every signal goes to PATH; without it nothing is dumped. $dumpvars without a scope
// takes the whole design, whose top is the bench that includes this, under both
// simulators (Icarus notes that it skips the $unit package; Verilator dumps only a bench
// built with --trace and otherwise says it ignored the call).
reg [8*1024-1:0] check_vcd;
initial
    if ($value$plusargs("vcd=%s", check_vcd)) begin
        $dumpfile(check_vcd);
        $dumpvars(0);
    end
