//! The ray tracer's scene as the user writes it (docs/requirements.md §4.11) and as the
//! host sends it: parsed into the model's [`Scene`](sim_target::rt::Scene), then written
//! into the register image a board receives.

mod build;
mod compile;
mod file;
pub mod range;
mod wire;

pub use build::{check_build, fit_build};
pub use compile::{to_regs, to_regs_as};
pub use file::{parse, parse_with_limits, Limits, SceneFileError};
pub use sim_target::scene_regs::{Regs, SceneRegsError};
pub use wire::{planned_scene, scene_wire_cost, WireCost};
