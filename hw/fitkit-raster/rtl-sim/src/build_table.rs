//! The builds the crate Verilates, one table read by both the library and the build
//! script (which includes this file), so a build's parameters are written once.

/// One Verilated build of the block: the top-level parameters of `fitkit_raster` it was
/// built with. The crate Verilates the four of [`Build::ALL`], each the one sim top
/// `fitkit_sim_top` (`hw/fitkit-raster/sim/`) with these parameters, as its own class;
/// its place in [`Build::ALL`] is the index the shim takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Build {
    /// The name `cargo xtask synth` gives the same variant.
    pub name: &'static str,
    /// The Verilated class, less its `V` (the shim names each).
    pub class: &'static str,
    /// `TRI_LANES`: the triangle unit's pixel tests per cycle.
    pub tri_lanes: u32,
    /// `LINE_UNIT`: the block has a line unit.
    pub line_unit: bool,
    /// `TRI_UNIT`: the block has a triangle unit.
    pub tri_unit: bool,
    /// `TRI_SMALL`: the triangle unit is `tri_small` (the XC3S50's: `TRI_LANES` = 1's
    /// pixels and cycles in fewer LUTs).
    pub tri_small: bool,
}

impl Build {
    /// The seed's block: both units, one pixel test per cycle.
    pub const DEFAULT: Build = Build {
        name: "default",
        class: "fitkit_sim_top",
        tri_lanes: 1,
        line_unit: true,
        tri_unit: true,
        tri_small: false,
    };
    /// Eight pixel tests per cycle.
    pub const TRI_LANES_8: Build = Build {
        name: "tri-lanes-8",
        class: "fitkit_sim_top8",
        tri_lanes: 8,
        ..Build::DEFAULT
    };
    /// Lines only, for the seed's XC3S50.
    pub const LINE: Build = Build {
        name: "line",
        class: "fitkit_sim_top_line",
        tri_unit: false,
        ..Build::DEFAULT
    };
    /// Triangles only, on the small triangle unit, for the seed's XC3S50.
    pub const TRI: Build = Build {
        name: "tri",
        class: "fitkit_sim_top_tri",
        line_unit: false,
        tri_small: true,
        ..Build::DEFAULT
    };
    /// Every build the crate Verilates, in the shim's order.
    pub const ALL: [Build; 4] = [Build::DEFAULT, Build::TRI_LANES_8, Build::LINE, Build::TRI];

    /// The sim top's parameters (`-G` to Verilator) that make this build.
    pub fn params(&self) -> [(&'static str, u32); 4] {
        [
            ("TRI_LANES", self.tri_lanes),
            ("LINE_UNIT", u32::from(self.line_unit)),
            ("TRI_UNIT", u32::from(self.tri_unit)),
            ("TRI_SMALL", u32::from(self.tri_small)),
        ]
    }
}
