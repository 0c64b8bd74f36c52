/*
 * Vitis HLS C testbench for the ray-trace block, for csim_design and cosim_design alike:
 * the DUT is given what the AXI4-Lite writes of `fpgfx vectors render` carry (replayed
 * from axi_writes.hex with the header's FPGFX_AXI_* addresses) and the texture memory,
 * the golden model (libfpgfx) renders the same frame from the same registers, and the two
 * are compared with the tolerances an hls_math build needs (docs/hls-testbench.md).
 *
 *   tb_viray VECTOR_DIR          (csim_design -argv VECTOR_DIR)
 *
 * Exit status 0: the frame passes; 1: it does not; 2: the vectors cannot be used.
 */
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fpgfx.h"
#include "viray.h"

/* The tolerances an hls_math build needs, with their reasons and the measurement behind
 * them in docs/hls-testbench.md: a channel may be off by one level, a depth sample by
 * 1e-5 relative, a normal component by 1e-4; beyond that, 1000 pixels per million (at
 * least one) may differ by any amount, where a shadow, reflection or hit decision flips
 * on a silhouette. */
static const uint8_t COLOUR_TOLERANCE = 1;
static const double DEPTH_TOLERANCE = 1e-5;
static const double NORMAL_TOLERANCE = 1e-4;
static const uint64_t OUTLIERS_PER_MILLION = 1000;

/* A $readmemh file as fpgfx writes it: hex words, `//` comments, `@addr` lines. */
static bool read_memh(const std::string &path, std::vector<uint64_t> &words) {
    FILE *f = std::fopen(path.c_str(), "r");
    if (!f) return false;
    char line[512];
    size_t addr = 0;
    while (std::fgets(line, sizeof line, f)) {
        if (char *c = std::strstr(line, "//")) *c = '\0';
        char *p = line;
        while (*p) {
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
            if (!*p) break;
            bool at = *p == '@';
            char *end;
            uint64_t v = std::strtoull(p + at, &end, 16);
            if (end == p + at) {
                std::fclose(f);
                return false;
            }
            p = end;
            if (at) {
                addr = (size_t)v;
                continue;
            }
            if (words.size() <= addr) words.resize(addr + 1, 0);
            words[addr++] = v;
        }
    }
    std::fclose(f);
    return true;
}

static bool read_bin(const std::string &path, std::vector<uint8_t> &bytes) {
    FILE *f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    uint8_t buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
    std::fclose(f);
    return true;
}

/* Samples of a float plane beyond `tol` (relative when `relative`), a hit on one side
 * and a miss (non-finite) on the other included. */
static uint64_t float_outliers(const float *want, const float *got, size_t n, double tol,
                               bool relative, double &worst) {
    uint64_t bad = 0;
    worst = 0;
    for (size_t i = 0; i < n; i++) {
        bool fw = std::isfinite(want[i]), fg = std::isfinite(got[i]);
        if (!fw || !fg) {
            bad += fw != fg;
            continue;
        }
        double e = std::fabs((double)got[i] - want[i]);
        if (relative && want[i] != 0) e /= std::fabs((double)want[i]);
        if (e > worst) worst = e;
        bad += e > tol;
    }
    return bad;
}

/* The block's ports, at their largest; static, as csim's stack is small. */
static uint32_t regs[FPGFX_SCENE_WORDS];
static uint32_t texture[FPGFX_TEXTURE_WORDS];
static uint8_t rgb[3 * VIRAY_MAX_PIXELS];
static float depth[VIRAY_MAX_PIXELS], normal[3 * VIRAY_MAX_PIXELS];

int main(int argc, char **argv) {
    std::string dir = argc > 1 ? argv[1] : "vectors";
    std::vector<uint64_t> writes;
    std::vector<uint8_t> tex;
    if (!read_memh(dir + "/axi_writes.hex", writes) || !read_bin(dir + "/texture.bin", tex) ||
        tex.size() != sizeof texture) {
        std::fprintf(stderr, "%s: no axi_writes.hex and texture.bin of fpgfx vectors render\n",
                     dir.c_str());
        return 2;
    }
    /* The AXI writes, as the block's s_axilite slave takes them. */
    fpgfx_start start = {0, 0};
    bool started = false;
    for (uint64_t wr : writes) {
        uint32_t addr = (uint32_t)(wr >> 32), data = (uint32_t)wr;
        if (addr >= FPGFX_AXI_SCENE_BASE && addr < FPGFX_AXI_SCENE_BASE + 4 * FPGFX_SCENE_WORDS)
            regs[(addr - FPGFX_AXI_SCENE_BASE) / 4] = data;
        else if (addr == FPGFX_AXI_NUMERIC)
            start.numeric = data;
        else if (addr == FPGFX_AXI_AOVS)
            start.aovs = data;
        else if (addr == FPGFX_AXI_AP_CTRL && (data & FPGFX_AXI_AP_START))
            started = true;
    }
    for (size_t i = 0; i < FPGFX_TEXTURE_WORDS; i++)
        texture[i] = (uint32_t)tex[4 * i] | (uint32_t)tex[4 * i + 1] << 8 |
                     (uint32_t)tex[4 * i + 2] << 16 | (uint32_t)tex[4 * i + 3] << 24;
    uint32_t w = 0, h = 0;
    if (!started || fpgfx_frame_size(regs, FPGFX_SCENE_WORDS, &w, &h) != FPGFX_OK ||
        (size_t)w * h > VIRAY_MAX_PIXELS) {
        std::fprintf(stderr, "%s: no frame to start (%s)\n", dir.c_str(), fpgfx_last_error());
        return 2;
    }
    size_t px = (size_t)w * h;

    /* The golden model, from the same registers and memory. */
    std::vector<uint8_t> want(3 * px);
    std::vector<float> want_depth(px), want_normal(3 * px);
    bool aovs = start.aovs != 0;
    if (fpgfx_render(regs, FPGFX_SCENE_WORDS, tex.data(), tex.size(), &start, want.data(),
                     want.size(), aovs ? want_depth.data() : NULL, aovs ? px : 0,
                     aovs ? want_normal.data() : NULL, aovs ? 3 * px : 0) != FPGFX_OK) {
        std::fprintf(stderr, "fpgfx_render: %s\n", fpgfx_last_error());
        return 2;
    }

    /* The DUT: C in csim, the RTL behind its wrapper in cosim. */
    viray(start.numeric, start.aovs, regs, texture, rgb, depth, normal);

    uint64_t budget = (px * OUTLIERS_PER_MILLION + 999999) / 1000000;
    fpgfx_compare_result c;
    if (fpgfx_compare_within(want.data(), rgb, 3 * px, w, h, COLOUR_TOLERANCE, &c) != FPGFX_OK) {
        std::fprintf(stderr, "fpgfx_compare_within: %s\n", fpgfx_last_error());
        return 2;
    }
    std::printf("%ux%u frame, outlier budget %llu pixels\n", w, h, (unsigned long long)budget);
    std::printf("colour: %llu pixels beyond %u level(s), largest difference %u\n",
                (unsigned long long)c.failing, COLOUR_TOLERANCE, c.max_difference);
    if (c.failing)
        std::printf("  first at (%u, %u): expected %02x%02x%02x, DUT %02x%02x%02x\n", c.first_x,
                    c.first_y, c.first_expected[0], c.first_expected[1], c.first_expected[2],
                    c.first_actual[0], c.first_actual[1], c.first_actual[2]);
    bool pass = c.failing <= budget;
    if (aovs) {
        double worst_d, worst_n;
        uint64_t d = float_outliers(want_depth.data(), depth, px, DEPTH_TOLERANCE, true, worst_d);
        uint64_t n =
            float_outliers(want_normal.data(), normal, 3 * px, NORMAL_TOLERANCE, false, worst_n);
        std::printf("depth: %llu samples beyond %g relative (largest %.3g)\n",
                    (unsigned long long)d, DEPTH_TOLERANCE, worst_d);
        std::printf("normal: %llu samples beyond %g (largest %.3g)\n", (unsigned long long)n,
                    NORMAL_TOLERANCE, worst_n);
        pass = pass && d <= budget && n <= 3 * budget;
    }
    std::printf("%s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
}
