/*
 * A stand-in DUT for running tb_viray.cpp outside Vitis HLS (capi/tests/c_test.rs does,
 * with g++): the golden model itself, made a little wrong on request, as a DUT whose
 * arithmetic is off would be. VIRAY_MODEL_ERROR=N raises every N-th colour channel by
 * VIRAY_MODEL_LEVELS levels (default 1) and scales depth and normal by 1 + 2^-20: what
 * the testbench's tolerances must pass at one level and fail at more. Replace this file
 * with the block's HLS source (viray.cpp) for csim and cosim.
 */
#include <cstdlib>

#include "viray.h"

void viray(uint32_t numeric, uint32_t aovs, const uint32_t regs[FPGFX_SCENE_WORDS],
           const uint32_t texture[FPGFX_TEXTURE_WORDS], uint8_t rgb[3 * VIRAY_MAX_PIXELS],
           float depth[VIRAY_MAX_PIXELS], float normal[3 * VIRAY_MAX_PIXELS]) {
    uint32_t w = 0, h = 0;
    if (fpgfx_frame_size(regs, FPGFX_SCENE_WORDS, &w, &h) != FPGFX_OK) return;
    size_t px = (size_t)w * h;
    fpgfx_start start = {numeric, aovs};
    fpgfx_render(regs, FPGFX_SCENE_WORDS, reinterpret_cast<const uint8_t *>(texture),
                 4 * FPGFX_TEXTURE_WORDS, &start, rgb, 3 * px, aovs ? depth : nullptr,
                 aovs ? px : 0, aovs ? normal : nullptr, aovs ? 3 * px : 0);
    const char *every = std::getenv("VIRAY_MODEL_ERROR");
    if (!every) return;
    long n = std::atol(every);
    const char *levels = std::getenv("VIRAY_MODEL_LEVELS");
    int up = levels ? std::atoi(levels) : 1;
    for (size_t i = 0; n > 0 && i < 3 * px; i += (size_t)n)
        rgb[i] = rgb[i] + up > 255 ? (uint8_t)(rgb[i] - up) : (uint8_t)(rgb[i] + up);
    for (size_t i = 0; aovs && i < px; i++) depth[i] *= 1.0f + 1.0f / (1 << 20);
    for (size_t i = 0; aovs && i < 3 * px; i++) normal[i] *= 1.0f + 1.0f / (1 << 20);
}
