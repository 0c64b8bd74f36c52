//! What the plan sends: the register image of a scene with every word the plan does not
//! use left at its power-on value, and the link bytes it costs to send it.
//!
//! The register diff (`protocol::scene::diff`) only sends words that differ from the
//! target's current image, so an unused word costs nothing once it is zero. The plan zeroes
//! the words no kernel reads for this scene: the reflection block when the traced depth is
//! 1, specular and diffuse terms when no point/spot light reaches a surface, ambient terms
//! when the ambient light is black, textures nothing samples. The device renders the same
//! image from either image (tested in `tests/rt_plan.rs`).

use sim_target::rt::{plan, DiffuseModel, Plan, Reflection, Scene};
use sim_target::scene_regs::{Regs, SceneRegsError};

use super::compile::to_regs;
use protocol::frame::{encode, HostFrame};
use protocol::link::{encode_frame, Header, Kind};
use protocol::scene::{diff_with_gap, DEFAULT_MERGE_GAP};

/// The scene as the plan sends it: unused terms removed (see the module docs).
pub fn planned_scene(scene: &Scene, plan: &Plan) -> Scene {
    let mut s = scene.clone();
    s.depth = plan.depth;
    let lit = !s.lights.is_empty();
    let ambient_lit = s.ambient.iter().any(|c| *c != 0.0);
    for m in &mut s.materials {
        if plan.depth == 1 {
            m.reflection = Reflection::None;
        }
        if !lit {
            m.specular = None;
            m.diffuse.k = 0.0;
            m.diffuse.color = [0.0; 3];
            m.diffuse_model = DiffuseModel::Lambert;
        }
        if !ambient_lit {
            m.ambient = None;
        }
        if !lit && m.ambient.is_none() {
            m.texture = None;
        }
    }
    if !lit {
        s.shadows = false;
    }
    s
}

/// Register words and link bytes of sending a scene to a target at power-on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WireCost {
    /// Words that differ from power-on: what must reach the target.
    pub changed: usize,
    /// Register words written (changed words plus bridged gaps).
    pub words: usize,
    /// `Regs` messages.
    pub writes: usize,
    /// Bytes on the link: postcard payload, 6-byte header, CRC-32, COBS and delimiter.
    pub bytes: usize,
    /// Unchanged words a run bridges (`protocol::scene::diff_with_gap`).
    pub gap: usize,
}

/// Cost of sending `regs` to a target at power-on with today's merge gap.
fn wire_cost(regs: &Regs) -> WireCost {
    wire_cost_gap(regs, DEFAULT_MERGE_GAP)
}

/// The cheapest way (in link bytes) to send `regs`: the plan zeroes unused words, and a
/// zero costs one byte as a postcard varint, so bridging a longer run of them can beat
/// opening a new message (≈ 15 bytes of framing); every gap up to 16 is tried.
fn wire_cost_best(regs: &Regs) -> WireCost {
    (0..=16)
        .map(|g| wire_cost_gap(regs, g))
        .min_by_key(|c| (c.bytes, c.gap))
        .unwrap_or_default()
}

/// Cost of sending `regs` to a target at power-on, bridging up to `gap` unchanged words.
fn wire_cost_gap(regs: &Regs, gap: usize) -> WireCost {
    let empty = Regs::new();
    let mut c = WireCost {
        gap,
        ..WireCost::default()
    };
    c.changed = empty
        .words()
        .zip(regs.words())
        .filter(|(a, b)| a != b)
        .count();
    let mut payload = [0u8; 512];
    let mut frame = [0u8; 1024];
    for (seq, w) in diff_with_gap(&empty, regs, gap).enumerate() {
        c.words += w.words.len();
        c.writes += 1;
        let msg: HostFrame = HostFrame::Regs(w);
        if let Ok(p) = encode(&msg, &mut payload) {
            let header = Header {
                kind: Kind::Data,
                epoch: 0,
                seq: seq as u16,
                ack: 0,
                credit: 4,
            };
            if let Ok(n) = encode_frame(&header, p, &mut frame) {
                c.bytes += n;
            }
        }
    }
    c
}

/// Cost of the scene as `to_regs` writes it and `diff` sends it today, and as the plan
/// sends it (unused words zeroed, best merge gap).
pub fn scene_wire_cost(scene: &Scene) -> Result<(WireCost, WireCost), SceneRegsError> {
    let full = wire_cost(&to_regs(scene)?);
    let planned = wire_cost_best(&to_regs(&planned_scene(scene, &plan(scene)))?);
    Ok((full, planned))
}
