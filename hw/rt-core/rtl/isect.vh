// isect.vh -- the intersection datapaths' latencies, counted from the pair's input:
// included inside rt_isect, which aligns the three to the longest, and inside each
// datapath, which checks its own schedule against its figure here, so each has one home.
// Needs q16_lat.vh (or q16_ops.vh, which includes it) before it.
//   quadric: front Q_DOT_LAT + 1, disc Q_DOT_LAT, sqrt, the quotients' operands 3,
//            quotients, roots in order 1, height Q_DOT_LAT + 2 (isect_quadric)
//   flat:    quotient, hit point Q_DOT_LAT + 1, disk test Q_DOT_LAT + 2 (isect_flat)
//   cube:    quotients, slabs 3, pick 1 (isect_cube)

// not every includer names every figure
/* verilator lint_off UNUSEDPARAM */
localparam integer LAT_QUADRIC = 3 * Q_DOT_LAT + Q_SQRT_LAT + Q_DIV_LAT + 7;
localparam integer LAT_FLAT = Q_DIV_LAT + 2 * Q_DOT_LAT + 3;
localparam integer LAT_CUBE = Q_DIV_LAT + 4;
/* verilator lint_on UNUSEDPARAM */
