/*
 * The ray-trace block's top function as the testbench calls it: the DUT of
 * tb_viray.cpp. Argument order fixes the AXI4-Lite map HLS generates (protocol::axi_lite):
 * the scalars numeric (0x10) and aovs (0x18) first, then the register image regs, a
 * 2 KiB window at 0x800. texture, rgb, depth and normal are memory ports (m_axi), not in
 * the control bundle.
 */
#ifndef VIRAY_H
#define VIRAY_H

#include <stdint.h>

#include "fpgfx.h"

/* The largest frame the ports are sized for (the seed's 1920 x 1080). */
#define VIRAY_MAX_PIXELS (1920 * 1080)

void viray(uint32_t numeric, uint32_t aovs, const uint32_t regs[FPGFX_SCENE_WORDS],
           const uint32_t texture[FPGFX_TEXTURE_WORDS], uint8_t rgb[3 * VIRAY_MAX_PIXELS],
           float depth[VIRAY_MAX_PIXELS], float normal[3 * VIRAY_MAX_PIXELS]);

#endif
