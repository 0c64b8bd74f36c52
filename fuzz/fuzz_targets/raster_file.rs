//! Any text through the raster command-file parser (as TOML and as JSON); what parses is
//! drawn on the raster block (clipped to 64 × 64).
#![no_main]
use libfuzzer_sys::fuzz_target;
use sim_target::raster::Raster;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    for name in ["fuzz.toml", "fuzz.json"] {
        if let Ok(job) = host_cli::raster_file::parse(text, name) {
            let w = u32::from(job.setup.width).min(64);
            let h = u32::from(job.setup.height).min(64);
            if let Ok(mut block) = Raster::new(w, h, &job.setup) {
                for c in &job.cmds {
                    let _ = block.draw(c);
                }
            }
        }
    }
});
