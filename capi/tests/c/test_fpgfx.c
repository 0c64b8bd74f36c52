/*
 * libfpgfx from C, against test vectors: what a C or C++ testbench does with the library.
 *
 *   test_fpgfx [--render DIR]... [--raster DIR]...
 *
 * --render DIR: a directory written by `fpgfx vectors render`. The AXI4-Lite writes are
 * replayed into a register image and start parameters (decoded with the header's
 * FPGFX_AXI_* addresses, as a bus model would), the frame is rendered with fpgfx_render
 * from them and texture.bin, and colour, depth and normal must equal the expected files
 * bit for bit; each .bin must equal its .hex.
 *
 * --raster DIR: a directory written by `fpgfx vectors raster`: raster_setup.hex (layout,
 * width, height, subpixel bits, background r g b, aa pattern, aa samples, cull,
 * traversal: one word each), fifo_records.hex (per record a flag digit, 4 = last record of
 * its packet + the FIFO tag, then the record) and expected_framebuffer.hex (rgb332 on the
 * FITkit, rgb888 otherwise). The packets run through fpgfx_raster_push and the
 * framebuffer, read back in the file's format, must equal the expected one.
 *
 * Then the error paths: null pointers, wrong lengths, bad codes and a damaged register
 * image must give the documented status and a message naming the argument.
 *
 * Prints each failure, then "N passed, M failed"; exits 0 only when nothing failed.
 */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include "fpgfx.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned passed, failed;

#define CHECK(cond, ...)                                   \
    do {                                                   \
        if (cond) {                                        \
            passed++;                                      \
        } else {                                           \
            failed++;                                      \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);    \
            printf(__VA_ARGS__);                           \
            printf("\n");                                  \
        }                                                  \
    } while (0)

/* A status and, unless it is FPGFX_OK, that the message names `word`. */
static int status_is(fpgfx_status got, fpgfx_status want, const char *word) {
    const char *msg = fpgfx_last_error();
    if (got != want) {
        printf("  status %d, expected %d (%s)\n", (int)got, (int)want, msg);
        return 0;
    }
    if (want != FPGFX_OK && strstr(msg, word) == NULL) {
        printf("  message \"%s\" does not name %s\n", msg, word);
        return 0;
    }
    return 1;
}

/* The whole file, NUL-terminated; NULL (with a message) if it cannot be read. */
static char *read_file(const char *dir, const char *name, size_t *len) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "rb");
    if (!f) {
        printf("cannot open %s\n", path);
        return NULL;
    }
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            cap *= 2;
            char *bigger = realloc(buf, cap + 1);
            if (!bigger) {
                free(buf);
                buf = NULL;
            }
            buf = bigger;
        }
    }
    fclose(f);
    if (!buf) {
        printf("out of memory reading %s\n", path);
        return NULL;
    }
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}

/*
 * A $readmemh file as compare::memh writes it: one hex word per line, `//` comments (the
 * first one returned in `first_comment`, which holds a framebuffer header), `@addr` lines.
 * Returns the words (NULL on a malformed file, with a message).
 */
static uint64_t *read_memh(const char *dir, const char *name, size_t *count, char *first_comment,
                           size_t comment_len) {
    char *text = read_file(dir, name, NULL);
    if (!text) return NULL;
    size_t cap = 1024, n = 0, addr = 0;
    uint64_t *words = calloc(cap, sizeof *words);
    int have_comment = 0;
    if (first_comment) first_comment[0] = '\0';
    for (char *line = strtok(text, "\n"); line && words; line = strtok(NULL, "\n")) {
        char *c = strstr(line, "//");
        if (c) {
            if (!have_comment && first_comment) {
                const char *t = c + 2;
                while (*t == ' ') t++;
                snprintf(first_comment, comment_len, "%s", t);
                have_comment = 1;
            }
            *c = '\0';
        }
        for (char *tok = strtok_r(line, " \t\r", &c); tok; tok = strtok_r(NULL, " \t\r", &c)) {
            char *end;
            if (tok[0] == '@') {
                addr = (size_t)strtoull(tok + 1, &end, 16);
                if (*end) {
                    printf("%s: bad address %s\n", name, tok);
                    goto bad;
                }
                continue;
            }
            uint64_t w = strtoull(tok, &end, 16);
            if (*end) {
                printf("%s: bad word %s\n", name, tok);
                goto bad;
            }
            while (addr >= cap) {
                uint64_t *bigger = realloc(words, 2 * cap * sizeof *words);
                if (!bigger) goto bad;
                memset(bigger + cap, 0, cap * sizeof *words);
                words = bigger;
                cap *= 2;
            }
            words[addr++] = w;
            if (addr > n) n = addr;
        }
    }
    free(text);
    *count = n;
    return words;
bad:
    free(text);
    free(words);
    return NULL;
}

/* A framebuffer file: header `fpgfx framebuffer WxH rgb888`, words 0xRRGGBB -> bytes. */
static uint8_t *read_frame(const char *dir, const char *name, uint32_t *w, uint32_t *h) {
    char header[256];
    size_t n;
    uint64_t *words = read_memh(dir, name, &n, header, sizeof header);
    if (!words) return NULL;
    char format[16] = "";
    if (sscanf(header, "fpgfx framebuffer %ux%u %15s", w, h, format) != 3 ||
        strcmp(format, "rgb888") != 0 || (size_t)*w * *h != n) {
        printf("%s: header \"%s\" does not describe its %zu words as rgb888\n", name, header, n);
        free(words);
        return NULL;
    }
    uint8_t *rgb = malloc(3 * n);
    for (size_t i = 0; rgb && i < n; i++) {
        rgb[3 * i] = (uint8_t)(words[i] >> 16);
        rgb[3 * i + 1] = (uint8_t)(words[i] >> 8);
        rgb[3 * i + 2] = (uint8_t)words[i];
    }
    free(words);
    return rgb;
}

/* `len` bytes of the .bin file must equal `words` of `width` bytes each, little-endian. */
static void check_bin(const char *dir, const char *name, const uint64_t *words, size_t n,
                      size_t width) {
    size_t len;
    uint8_t *bin = (uint8_t *)read_file(dir, name, &len);
    CHECK(bin && len == n * width, "%s/%s: %zu bytes, %zu expected", dir, name, bin ? len : 0,
          n * width);
    if (!bin || len != n * width) {
        free(bin);
        return;
    }
    size_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t w = 0;
        for (size_t b = 0; b < width; b++) w |= (uint64_t)bin[i * width + b] << (8 * b);
        if (w != words[i] && bad++ == 0)
            printf("  %s word %zu: %llx, the .hex has %llx\n", name, i, (unsigned long long)w,
                   (unsigned long long)words[i]);
    }
    CHECK(bad == 0, "%s/%s: %zu words differ from the .hex", dir, name, bad);
    free(bin);
}

/* Rendered floats against the .hex bit patterns. */
static void check_plane(const char *dir, const char *name, const float *got, size_t n) {
    size_t count;
    uint64_t *want = read_memh(dir, name, &count, NULL, 0);
    CHECK(want && count == n, "%s/%s: %zu words, the frame has %zu", dir, name,
          want ? count : 0, n);
    if (want && count == n) {
        size_t bad = 0;
        for (size_t i = 0; i < n; i++) {
            uint32_t bits;
            memcpy(&bits, &got[i], sizeof bits);
            if (bits != (uint32_t)want[i] && bad++ == 0)
                printf("  %s word %zu: rendered %08x, expected %08llx\n", name, i, bits,
                       (unsigned long long)want[i]);
        }
        CHECK(bad == 0, "%s/%s: %zu of %zu words differ", dir, name, bad, n);
    }
    free(want);
}

/* What the AXI writes of one frame leave in the block: the image and the scalars. */
struct axi_frame {
    uint32_t regs[FPGFX_SCENE_WORDS];
    fpgfx_start start;
    int started;
};

static int replay_axi(const char *dir, struct axi_frame *f) {
    size_t n;
    uint64_t *writes = read_memh(dir, "axi_writes.hex", &n, NULL, 0);
    if (!writes) return 0;
    memset(f, 0, sizeof *f);
    int ok = 1;
    for (size_t i = 0; i < n; i++) {
        uint32_t addr = (uint32_t)(writes[i] >> 32), data = (uint32_t)writes[i];
        if (f->started) {
            printf("  axi write %zu (%#x) after ap_start\n", i, addr);
            ok = 0;
        }
        if (addr >= FPGFX_AXI_SCENE_BASE && addr < FPGFX_AXI_SCENE_BASE + 4 * FPGFX_SCENE_WORDS &&
            addr % 4 == 0) {
            f->regs[(addr - FPGFX_AXI_SCENE_BASE) / 4] = data;
        } else if (addr == FPGFX_AXI_NUMERIC) {
            f->start.numeric = data;
        } else if (addr == FPGFX_AXI_AOVS) {
            f->start.aovs = data;
        } else if (addr == FPGFX_AXI_AP_CTRL && (data & FPGFX_AXI_AP_START)) {
            f->started = 1;
        } else {
            printf("  axi write %zu to %#x is no register of the block\n", i, addr);
            ok = 0;
        }
    }
    free(writes);
    return ok && f->started;
}

/* One `fpgfx vectors render` directory. */
static void check_render(const char *dir) {
    printf("render %s\n", dir);
    struct axi_frame f;
    CHECK(replay_axi(dir, &f), "%s: axi_writes.hex does not start one frame", dir);
    size_t nregs;
    uint64_t *regs_hex = read_memh(dir, "scene_regs.hex", &nregs, NULL, 0);
    int same = regs_hex && nregs == FPGFX_SCENE_WORDS;
    for (size_t i = 0; same && i < nregs; i++) same = regs_hex[i] == f.regs[i];
    CHECK(same, "%s: the AXI writes do not carry scene_regs.hex", dir);
    free(regs_hex);

    size_t tex_len, ntex;
    uint8_t *tex = (uint8_t *)read_file(dir, "texture.bin", &tex_len);
    uint64_t *tex_hex = read_memh(dir, "texture.hex", &ntex, NULL, 0);
    if (tex_hex) check_bin(dir, "texture.bin", tex_hex, ntex, 4);
    free(tex_hex);

    uint32_t w = 0, h = 0, ew = 0, eh = 0;
    CHECK(status_is(fpgfx_frame_size(f.regs, FPGFX_SCENE_WORDS, &w, &h), FPGFX_OK, ""),
          "%s: fpgfx_frame_size", dir);
    uint8_t *expected = read_frame(dir, "expected_rgb888.hex", &ew, &eh);
    CHECK(expected && ew == w && eh == h, "%s: expected_rgb888.hex is not the %ux%u frame", dir,
          w, h);
    if (!expected || ew != w || eh != h || !tex) {
        free(expected);
        free(tex);
        return;
    }
    size_t px = (size_t)w * h;
    uint8_t *rgb = malloc(3 * px);
    float *depth = malloc(px * sizeof *depth);
    float *normal = malloc(3 * px * sizeof *normal);
    fpgfx_status s = fpgfx_render(f.regs, FPGFX_SCENE_WORDS, tex, tex_len, &f.start, rgb, 3 * px,
                                  depth, px, normal, 3 * px);
    CHECK(status_is(s, FPGFX_OK, ""), "%s: fpgfx_render: %s", dir, fpgfx_last_error());
    if (s == FPGFX_OK) {
        fpgfx_compare_result r;
        CHECK(status_is(fpgfx_compare_exact(expected, rgb, 3 * px, w, h, &r), FPGFX_OK, ""),
              "%s: fpgfx_compare_exact", dir);
        CHECK(r.failing == 0,
              "%s: %llu of %llu pixels differ from expected_rgb888.hex, first at (%u, %u): "
              "expected %02x%02x%02x, rendered %02x%02x%02x",
              dir, (unsigned long long)r.failing, (unsigned long long)r.pixels, r.first_x,
              r.first_y, r.first_expected[0], r.first_expected[1], r.first_expected[2],
              r.first_actual[0], r.first_actual[1], r.first_actual[2]);
        check_plane(dir, "expected_depth.hex", depth, px);
        check_plane(dir, "expected_normal.hex", normal, 3 * px);
        /* The same frame without the texture argument: the registers' textures. */
        uint8_t *again = malloc(3 * px);
        CHECK(status_is(fpgfx_render(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &f.start, again, 3 * px,
                                     NULL, 0, NULL, 0),
                        FPGFX_OK, "") &&
                  memcmp(again, rgb, 3 * px) == 0,
              "%s: rendering without texture memory gives another frame", dir);
        free(again);
    }
    size_t n;
    uint64_t *words;
    if ((words = read_memh(dir, "expected_rgb888.hex", &n, NULL, 0))) {
        /* .bin is bytes R, G, B: compare per channel. */
        uint64_t *bytes = malloc(3 * n * sizeof *bytes);
        for (size_t i = 0; i < n; i++) {
            bytes[3 * i] = (words[i] >> 16) & 0xff;
            bytes[3 * i + 1] = (words[i] >> 8) & 0xff;
            bytes[3 * i + 2] = words[i] & 0xff;
        }
        check_bin(dir, "expected_rgb888.bin", bytes, 3 * n, 1);
        free(bytes);
        free(words);
    }
    if ((words = read_memh(dir, "expected_kcu116.hex", &n, NULL, 0))) {
        CHECK(n == px, "%s: expected_kcu116.hex has %zu words for %zu pixels", dir, n, px);
        check_bin(dir, "expected_kcu116.bin", words, n, 2);
        free(words);
    }
    if ((words = read_memh(dir, "expected_depth.hex", &n, NULL, 0))) {
        check_bin(dir, "expected_depth.bin", words, n, 4);
        free(words);
    }
    if ((words = read_memh(dir, "expected_normal.hex", &n, NULL, 0))) {
        check_bin(dir, "expected_normal.bin", words, n, 4);
        free(words);
    }
    free(rgb);
    free(depth);
    free(normal);
    free(expected);
    free(tex);
}

/* fifo_records.hex as packets: each record's flag digit (bit 2 ends a packet, bits 1:0
 * the FIFO tag), then its hex digits; a wide record and its flag exceed 64 bits, so the
 * flag is split off by hand. `records` gets every record, `ends[i]` the index after
 * packet i's last record and `tags[i]` its tag; NULL on a malformed file. */
static uint64_t *read_fifo_records(const char *dir, size_t *count, size_t **ends, uint8_t **tags,
                                   size_t *packets) {
    char *text = read_file(dir, "fifo_records.hex", NULL);
    if (!text) return NULL;
    size_t lines = 1;
    for (const char *c = text; *c; c++) lines += *c == '\n';
    uint64_t *records = calloc(lines, sizeof *records);
    *ends = calloc(lines, sizeof **ends);
    *tags = calloc(lines, 1);
    size_t n = 0, p = 0;
    int open_packet = 0;
    char *save;
    for (char *line = strtok_r(text, "\n", &save); line && records && *ends && *tags;
         line = strtok_r(NULL, "\n", &save)) {
        if (strncmp(line, "//", 2) == 0 || line[0] == '\0') continue;
        char flag[2] = {line[0], '\0'}, *end;
        unsigned long f = strtoul(flag, &end, 16);
        uint64_t r = strtoull(line + 1, &end, 16);
        if (line[1] == '\0' || (*end && *end != '\r') || f > 7) {
            printf("fifo_records.hex: bad record line \"%s\"\n", line);
            goto bad;
        }
        records[n++] = r;
        open_packet = 1;
        if (f & 4) {
            (*ends)[p] = n;
            (*tags)[p++] = (uint8_t)(f & 3);
            open_packet = 0;
        }
    }
    if (open_packet) {
        printf("fifo_records.hex: the last packet has no end flag\n");
        goto bad;
    }
    free(text);
    *count = n;
    *packets = p;
    return records;
bad:
    free(text);
    free(records);
    free(*ends);
    free(*tags);
    *ends = NULL;
    *tags = NULL;
    return NULL;
}

/* One raster vector directory. */
static void check_raster(const char *dir) {
    printf("raster %s\n", dir);
    size_t n;
    uint64_t *s = read_memh(dir, "raster_setup.hex", &n, NULL, 0);
    CHECK(s && n == 11, "%s: raster_setup.hex holds %zu words, 11 expected", dir, s ? n : 0);
    if (!s || n != 11) {
        free(s);
        return;
    }
    uint32_t layout = (uint32_t)s[0];
    fpgfx_raster_setup setup = {
        .width = (uint16_t)s[1],
        .height = (uint16_t)s[2],
        .subpixel_bits = (uint8_t)s[3],
        .background = {(uint8_t)s[4], (uint8_t)s[5], (uint8_t)s[6]},
        .aa_pattern = (uint32_t)s[7],
        .aa_samples = (uint8_t)s[8],
        .cull = (uint32_t)s[9],
        .traversal = (uint32_t)s[10],
    };
    free(s);
    fpgfx_raster *r = NULL;
    CHECK(status_is(fpgfx_raster_new(layout, &setup, &r), FPGFX_OK, "") && r,
          "%s: fpgfx_raster_new: %s", dir, fpgfx_last_error());
    size_t *ends = NULL, packets = 0, bad = 0, start = 0;
    uint8_t *tags = NULL;
    uint64_t *rec = read_fifo_records(dir, &n, &ends, &tags, &packets);
    for (size_t i = 0; r && rec && i < packets; i++) {
        /* The FITkit's tag is the packet's SPI address; 0 is the set-up transaction,
         * which raster_setup.hex carries already. The other layouts have one channel. */
        uint8_t channel = layout == FPGFX_LAYOUT_FITKIT ? tags[i] : FPGFX_CHANNEL_STREAM;
        if (layout == FPGFX_LAYOUT_FITKIT && channel == 0) {
            start = ends[i];
            continue;
        }
        if (fpgfx_raster_push(r, channel, rec + start, ends[i] - start) != FPGFX_OK &&
            bad++ == 0)
            printf("  raster packet %zu: %s\n", i, fpgfx_last_error());
        start = ends[i];
    }
    CHECK(rec && bad == 0, "%s: %zu of %zu raster packets refused", dir, bad, packets);
    free(rec);
    free(ends);
    free(tags);

    char header[256];
    uint64_t *want = read_memh(dir, "expected_framebuffer.hex", &n, header, sizeof header);
    uint32_t w = 0, h = 0;
    char format[16] = "";
    int rgb332 = 0;
    int ok = want && sscanf(header, "fpgfx framebuffer %ux%u %15s", &w, &h, format) == 3 &&
             (size_t)w * h == n && w == setup.width && h == setup.height &&
             ((rgb332 = strcmp(format, "rgb332") == 0) || strcmp(format, "rgb888") == 0);
    CHECK(ok, "%s: expected_framebuffer.hex (\"%s\") is not the %ux%u framebuffer", dir, header,
          setup.width, setup.height);
    if (r && ok) {
        size_t px = (size_t)w * h, bpp = rgb332 ? 1 : 3;
        uint8_t *got = malloc(bpp * px);
        CHECK(status_is(fpgfx_raster_read(r, rgb332 ? FPGFX_PIXEL_RGB332 : FPGFX_PIXEL_RGB888, got,
                                          bpp * px),
                        FPGFX_OK, ""),
              "%s: fpgfx_raster_read", dir);
        size_t differ = 0, first = 0;
        uint64_t first_want = 0, first_got = 0;
        for (size_t i = 0; got && i < px; i++) {
            uint64_t g = rgb332 ? got[i]
                                : (uint64_t)got[3 * i] << 16 | (uint64_t)got[3 * i + 1] << 8 |
                                      got[3 * i + 2];
            if (g != want[i] && differ++ == 0) {
                first = i;
                first_want = want[i];
                first_got = g;
            }
        }
        CHECK(got && differ == 0,
              "%s: %zu pixels differ from expected_framebuffer.hex, first at (%zu, %zu): "
              "expected %0*llx, drawn %0*llx",
              dir, differ, first % w, first / w, rgb332 ? 2 : 6, (unsigned long long)first_want,
              rgb332 ? 2 : 6, (unsigned long long)first_got);
        free(got);
    }
    free(want);
    CHECK(status_is(fpgfx_raster_free(r), FPGFX_OK, ""), "fpgfx_raster_free");
}

/* Every documented refusal, on a valid register image. */
static void check_errors(const char *render_dir) {
    printf("errors\n");
    struct axi_frame f;
    if (!replay_axi(render_dir, &f)) {
        CHECK(0, "%s: no register image for the error checks", render_dir);
        return;
    }
    uint32_t w, h;
    fpgfx_frame_size(f.regs, FPGFX_SCENE_WORDS, &w, &h);
    size_t px = (size_t)w * h;
    uint8_t *rgb = malloc(3 * px);
    float *depth = malloc(px * sizeof *depth);
    fpgfx_start start = f.start;
#define RENDER(regs, n, tex, tl, st, out, ol, d, dl) \
    fpgfx_render(regs, n, tex, tl, st, out, ol, d, dl, NULL, 0)
    CHECK(status_is(RENDER(NULL, FPGFX_SCENE_WORDS, NULL, 0, &start, rgb, 3 * px, NULL, 0),
                    FPGFX_BAD_ARGUMENT, "regs"),
          "NULL regs");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS - 1, NULL, 0, &start, rgb, 3 * px, NULL, 0),
                    FPGFX_SIZE_MISMATCH, "n_regs"),
          "short register image");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, NULL, rgb, 3 * px, NULL, 0),
                    FPGFX_BAD_ARGUMENT, "start"),
          "NULL start");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &start, NULL, 3 * px, NULL, 0),
                    FPGFX_BAD_ARGUMENT, "rgb888_out"),
          "NULL output");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &start, rgb, 3 * px - 1, NULL, 0),
                    FPGFX_SIZE_MISMATCH, "out_len"),
          "short output");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &start, rgb, 3 * px, depth, px - 1),
                    FPGFX_SIZE_MISMATCH, "depth_out"),
          "short depth plane");
    fpgfx_start no_aovs = {start.numeric, 0};
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &no_aovs, rgb, 3 * px, depth, px),
                    FPGFX_BAD_ARGUMENT, "aovs"),
          "a plane without aovs");
    fpgfx_start bad_numeric = {99, 0};
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &bad_numeric, rgb, 3 * px, NULL, 0),
                    FPGFX_BAD_ARGUMENT, "numeric"),
          "an unknown number format");
    uint8_t *tex = calloc(4, FPGFX_TEXTURE_WORDS);
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, tex, 4 * FPGFX_TEXTURE_WORDS - 4, &start, rgb,
                           3 * px, NULL, 0),
                    FPGFX_SIZE_MISMATCH, "tex_len"),
          "short texture memory");
    tex[1] ^= 0x40; /* a texel the registers' textures do not produce */
    fpgfx_status s = RENDER(f.regs, FPGFX_SCENE_WORDS, tex, 4 * FPGFX_TEXTURE_WORDS, &start, rgb,
                            3 * px, NULL, 0);
    /* All-zero memory with one changed byte matches no scene's textures. */
    CHECK(status_is(s, FPGFX_UNSUPPORTED, "texture word"), "foreign texture memory");
    free(tex);
    uint32_t damaged[FPGFX_SCENE_WORDS];
    memcpy(damaged, f.regs, sizeof damaged);
    damaged[0] ^= 1; /* the magic word */
    CHECK(status_is(RENDER(damaged, FPGFX_SCENE_WORDS, NULL, 0, &start, rgb, 3 * px, NULL, 0),
                    FPGFX_BAD_REGISTERS, "regs"),
          "a damaged magic word");
    CHECK(status_is(RENDER(f.regs, FPGFX_SCENE_WORDS, NULL, 0, &start, rgb, 3 * px, NULL, 0),
                    FPGFX_OK, "") &&
              strcmp(fpgfx_last_error(), "") == 0,
          "a good call clears the last error");
    CHECK(status_is(fpgfx_frame_size(f.regs, FPGFX_SCENE_WORDS, NULL, &h), FPGFX_BAD_ARGUMENT,
                    "width"),
          "fpgfx_frame_size without width");
#undef RENDER

    fpgfx_compare_result c;
    CHECK(status_is(fpgfx_compare_exact(rgb, rgb, 3 * px - 3, w, h, &c), FPGFX_SIZE_MISMATCH,
                    "len"),
          "comparing a short frame");
    CHECK(status_is(fpgfx_compare_exact(rgb, NULL, 3 * px, w, h, &c), FPGFX_BAD_ARGUMENT,
                    "actual"),
          "comparing with NULL");
    uint8_t *other = malloc(3 * px);
    memcpy(other, rgb, 3 * px);
    other[3 * (px - 1) + 1] ^= 0x01;
    CHECK(status_is(fpgfx_compare_exact(rgb, other, 3 * px, w, h, &c), FPGFX_OK, "") &&
              c.failing == 1 && c.first_x == w - 1 && c.first_y == h - 1 &&
              c.max_difference == 1,
          "one changed level is one failing pixel at the end, found %llu at (%u, %u)",
          (unsigned long long)c.failing, c.first_x, c.first_y);
    CHECK(status_is(fpgfx_compare_within(rgb, other, 3 * px, w, h, 1, &c), FPGFX_OK, "") &&
              c.failing == 0 && c.max_difference == 1,
          "a tolerance of one level allows it");
    free(other);

    fpgfx_raster_setup setup = {.width = 16, .height = 8, .traversal = FPGFX_TRAVERSAL_TILES};
    fpgfx_raster *r = (fpgfx_raster *)&setup; /* must be overwritten with NULL */
    CHECK(status_is(fpgfx_raster_new(7, &setup, &r), FPGFX_BAD_ARGUMENT, "layout") && r == NULL,
          "an unknown layout");
    setup.cull = 9;
    CHECK(status_is(fpgfx_raster_new(FPGFX_LAYOUT_FITKIT, &setup, &r), FPGFX_BAD_ARGUMENT,
                    "cull"),
          "an unknown cull code");
    setup.cull = FPGFX_CULL_NONE;
    setup.width = 0;
    CHECK(status_is(fpgfx_raster_new(FPGFX_LAYOUT_FITKIT, &setup, &r), FPGFX_BAD_ARGUMENT, "set-up"),
          "a zero-width framebuffer");
    setup.width = 16;
    CHECK(status_is(fpgfx_raster_new(FPGFX_LAYOUT_FITKIT, &setup, NULL), FPGFX_BAD_ARGUMENT, "out"),
          "NULL out");
    CHECK(status_is(fpgfx_raster_new(FPGFX_LAYOUT_FITKIT, &setup, &r), FPGFX_OK, ""), "a 16x8 block");
    uint64_t junk[2] = {~0ull, ~0ull};
    CHECK(status_is(fpgfx_raster_push(r, 0x02, junk, 2), FPGFX_DEVICE_ERROR, "packet"),
          "a packet that does not decode");
    CHECK(status_is(fpgfx_raster_push(r, 0x02, NULL, 2), FPGFX_BAD_ARGUMENT, "records"),
          "NULL records");
    uint8_t small[16 * 8 * 3];
    CHECK(status_is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, small, sizeof small - 1),
                    FPGFX_SIZE_MISMATCH, "out_len"),
          "a short read-back buffer");
    CHECK(status_is(fpgfx_raster_read(r, 5, small, sizeof small), FPGFX_BAD_ARGUMENT, "format"),
          "an unknown pixel format");
    CHECK(status_is(fpgfx_raster_read(NULL, FPGFX_PIXEL_RGB888, small, sizeof small),
                    FPGFX_BAD_ARGUMENT, "raster"),
          "reading NULL");
    CHECK(status_is(fpgfx_raster_free(r), FPGFX_OK, ""), "free");
    CHECK(status_is(fpgfx_raster_free(NULL), FPGFX_OK, ""), "free(NULL)");
    free(rgb);
    free(depth);
}

int main(int argc, char **argv) {
    const char *first_render = NULL;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--render") == 0) {
            check_render(argv[i + 1]);
            if (!first_render) first_render = argv[i + 1];
        } else if (strcmp(argv[i], "--raster") == 0) {
            check_raster(argv[i + 1]);
        } else {
            CHECK(0, "unknown argument %s", argv[i]);
        }
    }
    if (argc % 2 == 0) CHECK(0, "%s takes --render DIR and --raster DIR pairs", argv[0]);
    if (first_render)
        check_errors(first_render);
    else
        CHECK(0, "no --render directory: the error checks need a register image");
    printf("%u passed, %u failed\n", passed, failed);
    return failed ? 1 : 0;
}
