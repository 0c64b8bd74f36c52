//! What several targets share: a byte reader that never fails (it yields zeros past the
//! end, so every input means something) and the example scenes as register images.
#![allow(dead_code)]
use std::sync::OnceLock;

use protocol::scene::ValueFormat;
use sim_target::scene_regs::Regs;

pub mod scene;

/// Words of the register image.
pub const WORDS: usize = Regs::WORDS;

/// Reads numbers off the front of the input; zeros once it is used up.
pub struct Bytes<'a>(pub &'a [u8]);

impl<'a> Bytes<'a> {
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    pub fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    pub fn u64(&mut self) -> u64 {
        u64::from(self.u32()) | u64::from(self.u32()) << 32
    }
    /// Up to `n` bytes (fewer at the end of the input).
    pub fn take(&mut self, n: usize) -> &'a [u8] {
        let (a, b) = self.0.split_at(n.min(self.0.len()));
        self.0 = b;
        a
    }
    /// The rest of the input.
    pub fn rest(&mut self) -> &'a [u8] {
        self.take(usize::MAX)
    }
}

/// The example scenes as the host writes them (Q16.16 and binary32 images), 4 × 4,
/// 1 spp, depth ≤ 4: valid images for a target to patch.
pub fn base_images() -> &'static [[u32; WORDS]] {
    static BASES: OnceLock<Vec<[u32; WORDS]>> = OnceLock::new();
    BASES.get_or_init(|| {
        let texts = [
            include_str!("../../../examples/reference.toml"),
            include_str!("../../../examples/rt/brdf.toml"),
            include_str!("../../../examples/rt/fresnel.toml"),
            include_str!("../../../examples/rt/shapes.toml"),
            include_str!("../../../examples/rt/textures.toml"),
        ];
        let mut out = Vec::new();
        for fmt in [ValueFormat::Q16_16, ValueFormat::Binary32] {
            for t in texts {
                let mut scene = jobs::scene::parse(t, "base.toml").expect("an example parses");
                scene.width = 4;
                scene.height = 4;
                scene.spp = 1;
                scene.depth = scene.depth.min(4);
                let regs = jobs::scene::to_regs_as(&scene, fmt).expect("an example compiles");
                let mut w = [0u32; WORDS];
                regs.to_words(&mut w).expect("a whole image");
                out.push(w);
            }
        }
        out
    })
}

/// An image from the input: byte 0 bit 7 clear, the words from word 0 with the rest from
/// base image `byte 0 >> 3 & 15`; set, that base patched by (u16 offset, u32 word) pairs
/// as RegWrite frames reach the device. Bits 0–2 of byte 0 are left to the caller.
pub fn image(ctl: u8, rest: &[u8]) -> [u32; WORDS] {
    let bases = base_images();
    let mut words = bases[usize::from(ctl >> 3 & 15) % bases.len()];
    if ctl & 0x80 == 0 {
        for (w, b) in words.iter_mut().zip(rest.chunks_exact(4)) {
            *w = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        }
    } else {
        for p in rest.chunks_exact(6) {
            let at = usize::from(u16::from_le_bytes([p[0], p[1]])) % WORDS;
            words[at] = u32::from_le_bytes([p[2], p[3], p[4], p[5]]);
        }
    }
    words
}

/// Clamps the image's frame to at most 8 × 8 pixels, 1 spp and depth 4, so that a
/// render stays short whatever the words say.
pub fn tiny(words: &mut [u32; WORDS]) {
    use protocol::scene::hdr;
    words[hdr::WIDTH] = words[hdr::WIDTH].min(8);
    words[hdr::HEIGHT] = words[hdr::HEIGHT].min(8);
    words[hdr::SPP] = words[hdr::SPP].min(1);
    words[hdr::DEPTH] = words[hdr::DEPTH].min(4);
}
