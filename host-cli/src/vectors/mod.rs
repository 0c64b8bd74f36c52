//! `fpgfx vectors`: test vectors for a hardware block, written from the golden model so
//! that a testbench outside this repository can check its DUT against it.

pub mod render;
