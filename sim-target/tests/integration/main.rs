//! sim-target's integration tests, one module per area: the AXI4-Lite register file, the
//! instrumented formats (bit
//! equality with their format, reentrant counting), the approximations' error bounds,
//! the rasteriser (coverage, anti-aliasing, primitives, hardware
//! model, golden framebuffer) and the ray tracer (accuracy, culling, golden images,
//! planned kernels, intersectors, textures, register image). One binary rather than one
//! per file: each test binary compiles and links the whole stack again (debug info, the
//! generic kernels instantiated per binary), so a single one is built and linked once.

mod common;

mod device_texels;

mod instrumented;
mod mmio;
mod num_approx;
mod raster_aa;
mod raster_aa_attrs;
mod raster_golden;
mod raster_hw;
mod raster_prims;
mod raster_tri;
mod rt_accuracy;
mod rt_cull;
mod rt_cull_secondary;
mod rt_flat_side;
mod rt_golden;
mod rt_golden_formats;
mod rt_golden_paths;
mod rt_packets;
mod rt_plan;
mod rt_precision;
mod rt_props;
mod rt_render;
mod rt_shapes;
mod rt_texture_fast;
mod saturation;
mod scene_regs;
