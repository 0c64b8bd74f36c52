// rt_light.vh -- rt_light's schedule: the stage at which each of its values is registered,
// counted from its input. Included inside rt_light and inside rt_shade, which meets the
// lanes' outputs (p, wi and dist, the term) at these stages, so the schedule has one home.
// Needs q16_lat.vh (or q16_ops.vh, which includes it) before it.

// not every includer names every stage
/* verilator lint_off UNUSEDPARAM */
localparam integer L_P = Q_DOT_LAT + 1;              // p = eye + d t
localparam integer L_TL = L_P + 1;                   // to_l = light - p
localparam integer L_D2 = L_TL + Q_DOT_LAT;          // dist2
localparam integer L_INV = L_D2 + Q_RSQRT_LAT;       // 1/sqrt(dist2)
localparam integer L_WI = L_INV + Q_DOT_LAT;         // wi and dist (the shadow ray)
localparam integer L_NDL = L_WI + Q_DOT_LAT;         // n.wi and "lit"
localparam integer L_G = L_NDL + Q_DIV_LAT;          // g = ndl / dist2
localparam integer L_H = L_WI + 1 + Q_NORM3_LAT;     // h
localparam integer L_NH = L_H + Q_DOT_LAT + 1;       // max(n.h, 0)
localparam integer L_FS = L_NH + Q_POWI_LAT + Q_DOT_LAT;  // fs = norm nh^e
localparam integer L_BRDF = L_FS + Q_DOT_LAT + 1;    // brdf
localparam integer L_LAT = L_BRDF + 2 * Q_DOT_LAT;   // the term
/* verilator lint_on UNUSEDPARAM */
