// q16_lat.vh -- the Q16.16 arithmetic units' latencies, included inside a module (and by
// q16_ops.vh): every schedule behind a product, quotient or root is written in these, so
// a unit's pipeline depth has one home. tb_units holds each unit to its figure.

// not every includer names every latency
/* verilator lint_off UNUSEDPARAM */
// q16_dot's latency: operands, partial products, term products, sum. Every schedule
// behind a product is written in it, so the pipeline depth of the products lives here.
localparam integer Q_DOT_LAT = 4;
// The other units' latencies, as their headers state them (tb_units holds each unit to
// its figure): q16_div, q16_sqrt, q16_rsqrt; q16_norm3 is v.v, 1/sqrt and the scaling
// product; q16_powi ten products.
localparam integer Q_DIV_LAT = 35;
localparam integer Q_SQRT_LAT = 27;
localparam integer Q_RSQRT_LAT = 79;
localparam integer Q_NORM3_LAT = 2 * Q_DOT_LAT + Q_RSQRT_LAT;
localparam integer Q_POWI_LAT = 10 * Q_DOT_LAT;
/* verilator lint_on UNUSEDPARAM */
