//! The hardware model: input FIFO with FIFO_FREE back-pressure, fragment FIFO and cycle
//! counters, so that `--stats` can say what the board would have taken.

use std::collections::VecDeque;

/// Records in the input FIFO: seed 000's RAMB16_S36_S36, whatever the bus layout, so the
/// FITkit's figure (its home is the SPI contract) is the model's too.
pub const FIFO_DEPTH: u32 = protocol::fitkit_spi::FIFO_RECORDS as u32;
/// Bits per input FIFO record.
pub const RECORD_BITS: u32 = protocol::fitkit_spi::RECORD_BITS;
/// Fragment FIFO between the raster units and the SDRAM writer.
pub const FRAG_FIFO_DEPTH: u64 = 16;
/// Clock of seed 000's line block, used for the board-time estimate.
pub const CLOCK_HZ: f64 = 142e6;
/// Cycles of a triangle's set-up before its first traversal step, as the RTL's triangle
/// unit spends them with `lanes` pixels per step (docs/rtl.md): one to take the box's
/// offsets, ten more for the edge products one multiplier bit per clock, two for the
/// orientation and the edge values, `log2 lanes + 1` to give each lane its columns and
/// the row below, and two to fill the queue in front of the fragment stream.
pub fn tri_setup_cycles(lanes: u32) -> u64 {
    16 + u64::from(lanes.max(1).ilog2())
}
/// Cycles of a triangle the RTL's unit draws nothing of (degenerate, culled or off the
/// frame): its set-up up to the orientation, whatever the lanes (and the small unit's
/// too, which waits for that cycle).
pub const TRI_REJECT_CYCLES: u64 = 13;
/// Cycles of the small triangle unit's set-up (`tri_small`, the XC3S50's: its set-up's
/// seventeen products one at a time through one multiplier, then the first step) before
/// its walk, which is the one-lane unit's (docs/rtl.md).
pub const TRI_SMALL_SETUP_CYCLES: u64 = 18;
/// Cycles of a line's set-up (the deltas' magnitudes, the major axis, the Bresenham
/// decision variable) before its first pixel, as the RTL's line unit spends them
/// (docs/rtl.md).
pub const LINE_SETUP_CYCLES: u64 = 3;

/// The cycles a unit of the RTL is busy for a command when the memory holds its wait
/// input high on the cycles `wait` marks (index 0: the unit's first cycle; past its end,
/// never). The unit spends `setup` cycles that emit nothing, then one step per entry of
/// `steps`: `true` hands a fragment to the fragment FIFO ([`FRAG_FIFO_DEPTH`] entries)
/// and waits while it is full, `false` emits nothing and never waits. Behind the FIFO the
/// writer holds one memory request: it takes the FIFO's head whenever its request is
/// empty or accepted, and the memory accepts a request on every cycle its wait is low.
/// The FIFO starts empty and the writer idle, as after every command the RTL finishes.
/// This is how the RTL's line, clear and triangle units stall (docs/rtl.md), so with the
/// memory's wait pattern the model's cycles are the RTL's.
pub fn stalled_cycles(setup: u64, steps: impl IntoIterator<Item = bool>, wait: &[bool]) -> u64 {
    let held = |t: u64| usize::try_from(t).ok().and_then(|i| wait.get(i)) == Some(&true);
    let mut steps = steps.into_iter().peekable();
    let (mut t, mut queued, mut request) = (0u64, 0u64, false);
    loop {
        let full = queued == FRAG_FIFO_DEPTH;
        let mut push = false;
        if t >= setup {
            match steps.peek() {
                None => return t,
                Some(&emits) if emits && full => {}
                Some(&emits) => {
                    push = emits;
                    steps.next();
                }
            }
        }
        let accept = request && !held(t);
        let take = !request || accept;
        let pop = take && queued > 0;
        if take {
            request = pop;
        }
        queued = queued + u64::from(push) - u64::from(pop);
        t += 1;
        if t >= setup && steps.peek().is_none() {
            return t;
        }
    }
}

/// Which block a command ran on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// Triangles and patches.
    Triangle,
    /// Lines and Bézier polylines.
    Line,
    /// Midpoint circles.
    Circle,
    /// Seed and polygon fills.
    Fill,
    /// Framebuffer clears.
    Clear,
}

/// Cycle counters per block.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BlockCycles {
    /// Triangle block (edge functions, traversal).
    pub triangle: u64,
    /// Line block (Bresenham/DDA, thick, AA, Bézier segments).
    pub line: u64,
    /// Circle block (midpoint outlines and filled circles).
    pub circle: u64,
    /// Fill block (seed fill, polygon spans).
    pub fill: u64,
    /// Clear (one pixel per cycle, the SDRAM write rate).
    pub clear: u64,
}

/// Counters the device reports. Cycles are the model's, not the host's time.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Commands executed, refused ones not counted.
    pub commands: u64,
    /// Fragments written to the framebuffer.
    pub fragments: u64,
    /// Single-pixel inside tests.
    pub pixel_tests: u64,
    /// Block/tile classifications.
    pub block_tests: u64,
    /// Busy cycles per block.
    pub cycles: BlockCycles,
    /// Cycle at which the last command finished (input side included).
    pub end_cycle: u64,
    /// Input FIFO records pushed.
    pub fifo_records: u64,
    /// Cycles the controller waited on FIFO_FREE (full FIFO).
    pub fifo_stalls: u64,
    /// Highest input FIFO occupancy seen, in records.
    pub fifo_max: u32,
    /// Cycles a block waited on a full fragment FIFO.
    pub fragment_stalls: u64,
}

impl Stats {
    /// Busy cycles summed over blocks.
    pub fn total_cycles(&self) -> u64 {
        let c = &self.cycles;
        c.triangle + c.line + c.circle + c.fill + c.clear
    }

    /// Board time at [`CLOCK_HZ`], from the end cycle (blocks run one command at a time).
    pub fn board_seconds(&self) -> f64 {
        self.end_cycle as f64 / CLOCK_HZ
    }
}

/// Timing state: the controller pushes records at `push_period` cycles each; the block
/// pops a command's records when it starts it and runs commands in order.
#[derive(Debug, Clone)]
pub struct Model {
    /// Cycles per pushed record (1 = bus-speed; the FITkit SPI is far slower).
    pub push_period: u64,
    now: u64,
    block_free: u64,
    queued: VecDeque<(u64, u32)>,
    /// Sum of `queued` records, kept incrementally (the queue can hold 512 entries).
    occ: u32,
}

impl Default for Model {
    fn default() -> Self {
        Self {
            push_period: 1,
            now: 0,
            block_free: 0,
            queued: VecDeque::new(),
            occ: 0,
        }
    }
}

impl Model {
    fn occupancy(&mut self) -> u32 {
        let now = self.now;
        while let Some(&(start, r)) = self.queued.front() {
            if start > now {
                break;
            }
            self.queued.pop_front();
            self.occ -= r;
        }
        self.occ
    }

    /// Accounts work of `records` FIFO records that keeps `unit` busy for `busy` cycles
    /// producing `fragments` fragments, written `lanes` per cycle (the writer is as wide
    /// as the block: an 8-lane block writes 8-pixel SDRAM bursts). It does not count a
    /// command: the caller knows whether this is one (a set-up's clear is not, and a CB
    /// draw's clear and draw are one packet).
    pub fn command(
        &mut self,
        stats: &mut Stats,
        unit: Unit,
        records: u32,
        busy: u64,
        fragments: u64,
        lanes: u64,
    ) {
        let records = records.min(FIFO_DEPTH);
        // Back-pressure: wait until the block has popped enough records.
        while self.occupancy() + records > FIFO_DEPTH {
            let Some(&(start, _)) = self.queued.front() else {
                break;
            };
            stats.fifo_stalls += start - self.now;
            self.now = start;
        }
        self.now += records as u64 * self.push_period;
        stats.fifo_records += records as u64;
        // The writer drains `lanes` fragments per cycle; the FIFO hides short bursts.
        let drain = fragments
            .saturating_sub(FRAG_FIFO_DEPTH)
            .div_ceil(lanes.max(1));
        let stall = drain.saturating_sub(busy);
        stats.fragment_stalls += stall;
        let busy = busy + stall;
        let start = self.now.max(self.block_free);
        self.block_free = start + busy;
        self.queued.push_back((start, records));
        self.occ += records;
        let occ = self.occupancy();
        stats.fifo_max = stats.fifo_max.max(occ);
        stats.end_cycle = self.block_free.max(self.now);
        let c = &mut stats.cycles;
        match unit {
            Unit::Triangle => c.triangle += busy,
            Unit::Line => c.line += busy,
            Unit::Circle => c.circle += busy,
            Unit::Fill => c.fill += busy,
            Unit::Clear => c.clear += busy,
        }
    }
}
