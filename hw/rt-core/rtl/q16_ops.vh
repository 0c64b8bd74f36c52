// q16_ops.vh -- the golden model's one-cycle Q16.16 operations as functions, included
// inside a module: saturating +, -, negation and |x| (sim-target/src/num/formats.rs:
// `checked_add` / `saturating_add`, `checked_neg` clipping -2^31 to 2^31 - 1, `abs`
// saturating likewise), and the constants the kernel writes as `S::one()` and
// `S::from_f64(..)`. Combinational: the caller registers the result where its schedule
// says.

// not every includer names every constant
/* verilator lint_off UNUSEDPARAM */
localparam [31:0] Q_ONE = 32'h0001_0000;
localparam [31:0] Q_MAX = 32'h7fff_ffff;
localparam [31:0] Q_MIN = 32'h8000_0000;
/* verilator lint_on UNUSEDPARAM */
`include "q16_lat.vh"

function [31:0] q_add(input [31:0] qa, input [31:0] qb);
    reg [32:0] s;
    begin
        s = {qa[31], qa} + {qb[31], qb};
        if (s[32] != s[31]) q_add = s[32] ? Q_MIN : Q_MAX;
        else q_add = s[31:0];
    end
endfunction

function [31:0] q_sub(input [31:0] qa, input [31:0] qb);
    reg [32:0] s;
    begin
        s = {qa[31], qa} - {qb[31], qb};
        if (s[32] != s[31]) q_sub = s[32] ? Q_MIN : Q_MAX;
        else q_sub = s[31:0];
    end
endfunction

function [31:0] q_neg(input [31:0] qa);
    q_neg = qa == Q_MIN ? Q_MAX : 32'd0 - qa;
endfunction

function [31:0] q_abs(input [31:0] qa);
    q_abs = qa[31] ? q_neg(qa) : qa;
endfunction

// qa < qb, qa <= qb as signed words
function q_lt(input [31:0] qa, input [31:0] qb);
    q_lt = $signed(qa) < $signed(qb);
endfunction

function q_le(input [31:0] qa, input [31:0] qb);
    q_le = $signed(qa) <= $signed(qb);
endfunction
