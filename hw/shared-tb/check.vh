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
