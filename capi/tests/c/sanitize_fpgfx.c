/*
 * libfpgfx from C under AddressSanitizer and UndefinedBehaviorSanitizer: every function
 * called with adversarial arguments, as a careless testbench would call it.
 *
 *   sanitize_fpgfx [FILE]...
 *
 * Built with -fsanitize=address,undefined -fno-sanitize-recover=all (capi/tests/c_test.rs),
 * so a read or write past a buffer, a use after free or a double free on either side of
 * the boundary that goes through malloc or the C library stops the program. Every buffer
 * is a malloc'd block of exactly the length passed, so one byte too far is caught.
 *
 * Checked: NULL for each pointer, misaligned pointers, lengths 0, one short, one long and
 * SIZE_MAX, codes that name nothing, sizes whose products overflow, register images made
 * of each FILE's bytes (the fuzz corpus: malformed on purpose), raster blocks freed and
 * pushed in every order the header allows. Each call must return the status the header
 * documents and fpgfx_last_error() must be "" after FPGFX_OK and name the argument
 * otherwise; FPGFX_INTERNAL_ERROR (a caught panic) is always a failure.
 *
 * Prints each failure, then "N passed, M failed"; exits 0 only when nothing failed.
 */
#include "fpgfx.h"

#include <stdint.h>
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

/* The status is `want` and the message starts with `word` ("" after FPGFX_OK). */
static int is(fpgfx_status got, fpgfx_status want, const char *word) {
    const char *msg = fpgfx_last_error();
    if (msg == NULL) {
        printf("  fpgfx_last_error() is NULL\n");
        return 0;
    }
    if (got != want) {
        printf("  status %d, expected %d (\"%s\")\n", (int)got, (int)want, msg);
        return 0;
    }
    if (want == FPGFX_OK) {
        if (msg[0] != '\0') {
            printf("  FPGFX_OK with message \"%s\"\n", msg);
            return 0;
        }
        return 1;
    }
    if (strncmp(msg, word, strlen(word)) != 0) {
        printf("  message \"%s\" does not start with \"%s\"\n", msg, word);
        return 0;
    }
    return 1;
}

/* Any status but FPGFX_INTERNAL_ERROR, with a message exactly when it is not FPGFX_OK. */
static int documented(fpgfx_status got) {
    const char *msg = fpgfx_last_error();
    if ((int)got < 0 || got > FPGFX_INTERNAL_ERROR || got == FPGFX_INTERNAL_ERROR) {
        printf("  status %d (\"%s\")\n", (int)got, msg);
        return 0;
    }
    return (got == FPGFX_OK) == (msg[0] == '\0');
}

/* A malloc'd block of exactly n bytes (at least 1, so that a 0-length buffer has a
 * non-NULL address ASan still guards). */
static void *block(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) {
        printf("out of memory\n");
        exit(2);
    }
    memset(p, 0xa5, n ? n : 1);
    return p;
}

static fpgfx_raster_setup small_setup(void) {
    fpgfx_raster_setup s;
    memset(&s, 0, sizeof s);
    s.width = 5;
    s.height = 3;
    s.background[0] = 10;
    s.background[1] = 20;
    s.background[2] = 30;
    s.aa_pattern = FPGFX_AA_NONE;
    s.cull = FPGFX_CULL_NONE;
    s.traversal = FPGFX_TRAVERSAL_TILES;
    return s;
}

static void raster_calls(void) {
    fpgfx_raster_setup s = small_setup();
    fpgfx_raster *r = (fpgfx_raster *)&s; /* garbage the call must overwrite */

    CHECK(is(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, NULL, &r), FPGFX_BAD_ARGUMENT, "setup"),
          "raster_new(setup NULL)");
    CHECK(r == NULL, "raster_new left *out set after a failure");
    CHECK(is(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, NULL), FPGFX_BAD_ARGUMENT, "out"),
          "raster_new(out NULL)");
    CHECK(is(fpgfx_raster_new(3, &s, &r), FPGFX_BAD_ARGUMENT, "layout"), "layout 3");
    CHECK(is(fpgfx_raster_new(UINT32_MAX, &s, &r), FPGFX_BAD_ARGUMENT, "layout"),
          "layout UINT32_MAX");
    s.aa_pattern = 6;
    CHECK(is(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, &r), FPGFX_BAD_ARGUMENT,
             "setup->aa_pattern"), "aa_pattern 6");
    s = small_setup();
    s.cull = 0x80000000u;
    CHECK(is(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, &r), FPGFX_BAD_ARGUMENT, "setup->cull"),
          "cull");
    s = small_setup();
    s.traversal = 5;
    CHECK(is(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, &r), FPGFX_BAD_ARGUMENT,
             "setup->traversal"), "traversal 5");
    s = small_setup();
    s.width = 0;
    CHECK(documented(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, &r)) && r == NULL,
          "a 0-wide framebuffer is refused");
    s = small_setup();
    s.aa_pattern = FPGFX_AA_REGULAR;
    s.aa_samples = 255;
    CHECK(documented(fpgfx_raster_new(FPGFX_LAYOUT_WIDE, &s, &r)), "255 AA samples");
    fpgfx_raster_free(r);
    s = small_setup();
    s.subpixel_bits = 255;
    CHECK(documented(fpgfx_raster_new(FPGFX_LAYOUT_FITKIT, &s, &r)), "255 sub-pixel bits");
    fpgfx_raster_free(r);

    for (uint32_t layout = 0; layout < 3; layout++) {
        s = small_setup();
        r = NULL;
        if (!is(fpgfx_raster_new(layout, &s, &r), FPGFX_OK, "")) {
            CHECK(0, "raster_new on layout %u", (unsigned)layout);
            continue;
        }
        CHECK(r != NULL, "raster_new OK without a block");
        size_t n888 = (size_t)s.width * s.height * 3, n332 = (size_t)s.width * s.height;
        uint8_t *exact = block(n888), *shorter = block(n888 - 1), *longer = block(n888 + 1);
        CHECK(is(fpgfx_raster_read(NULL, FPGFX_PIXEL_RGB888, exact, n888),
                 FPGFX_BAD_ARGUMENT, "raster"), "read(raster NULL)");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, NULL, n888), FPGFX_BAD_ARGUMENT,
                 "out"), "read(out NULL)");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, shorter, n888 - 1),
                 FPGFX_SIZE_MISMATCH, "out_len"), "read one byte short");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, longer, n888 + 1),
                 FPGFX_SIZE_MISMATCH, "out_len"), "read one byte long");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, exact, SIZE_MAX),
                 FPGFX_SIZE_MISMATCH, "out_len"), "read SIZE_MAX");
        CHECK(is(fpgfx_raster_read(r, 2, exact, n888), FPGFX_BAD_ARGUMENT, "format"),
              "format 2");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, exact, n888), FPGFX_OK, ""),
              "read exact");
        CHECK(layout == FPGFX_LAYOUT_FITKIT ||
                  (exact[0] == 10 && exact[1] == 20 && exact[2] == 30 && exact[n888 - 1] == 30),
              "the cleared framebuffer is the background");
        uint8_t *small = block(n332);
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB332, small, n332), FPGFX_OK, ""),
              "read rgb332");
        free(small);

        uint64_t *records = block(8 * sizeof(uint64_t));
        memset(records, 0xff, 8 * sizeof(uint64_t));
        CHECK(is(fpgfx_raster_push(NULL, FPGFX_CHANNEL_STREAM, records, 1),
                 FPGFX_BAD_ARGUMENT, "raster"), "push(raster NULL)");
        CHECK(is(fpgfx_raster_push(r, FPGFX_CHANNEL_STREAM, NULL, 0), FPGFX_BAD_ARGUMENT,
                 "records"), "push(records NULL, 0)");
        CHECK(is(fpgfx_raster_push(r, FPGFX_CHANNEL_STREAM,
                                   (const uint64_t *)((const char *)records + 1), 1),
                 FPGFX_BAD_ARGUMENT, "records"), "push(records misaligned)");
        CHECK(is(fpgfx_raster_push(r, FPGFX_CHANNEL_STREAM, records, SIZE_MAX),
                 FPGFX_SIZE_MISMATCH, "records"), "push(SIZE_MAX records)");
        for (unsigned ch = 0; ch < 8; ch++) {
            for (size_t n = 0; n <= 8; n++) {
                fpgfx_status st = fpgfx_raster_push(r, (uint8_t)ch, records, n);
                CHECK(documented(st) && st != FPGFX_SIZE_MISMATCH,
                      "push %zu all-ones records on channel %u: %d", n, ch, (int)st);
            }
        }
        /* Zero records: an empty packet. */
        memset(records, 0, 8 * sizeof(uint64_t));
        CHECK(documented(fpgfx_raster_push(r, FPGFX_CHANNEL_STREAM, records, 8)),
              "push zero records");
        CHECK(is(fpgfx_raster_read(r, FPGFX_PIXEL_RGB888, exact, n888), FPGFX_OK, ""),
              "the block reads back after refused packets");
        free(records);
        free(exact);
        free(shorter);
        free(longer);
        CHECK(is(fpgfx_raster_free(r), FPGFX_OK, ""), "free");
    }
    CHECK(is(fpgfx_raster_free(NULL), FPGFX_OK, ""), "free(NULL)");
}

/* Reference counts for a comparison. */
static void recount(const uint8_t *e, const uint8_t *a, size_t pixels, uint8_t tol,
                    uint64_t *failing, uint8_t *max) {
    *failing = 0;
    *max = 0;
    for (size_t i = 0; i < pixels; i++) {
        uint8_t d = 0;
        for (int c = 0; c < 3; c++) {
            int x = e[3 * i + c] - a[3 * i + c];
            uint8_t ad = (uint8_t)(x < 0 ? -x : x);
            if (ad > d) d = ad;
        }
        if (d > *max) *max = d;
        if (d > tol) (*failing)++;
    }
}

static void compare_calls(void) {
    const uint32_t w = 7, h = 5;
    const size_t n = (size_t)w * h * 3;
    uint8_t *e = block(n), *a = block(n);
    for (size_t i = 0; i < n; i++) {
        e[i] = (uint8_t)(i * 37);
        a[i] = (uint8_t)(i * 37 + (i % 11 == 0 ? (i % 3) * 5 : 0));
    }
    fpgfx_compare_result out;
    CHECK(is(fpgfx_compare_exact(NULL, a, n, w, h, &out), FPGFX_BAD_ARGUMENT, "expected"),
          "compare(expected NULL)");
    CHECK(is(fpgfx_compare_exact(e, NULL, n, w, h, &out), FPGFX_BAD_ARGUMENT, "actual"),
          "compare(actual NULL)");
    CHECK(is(fpgfx_compare_exact(e, a, n, w, h, NULL), FPGFX_BAD_ARGUMENT, "out"),
          "compare(out NULL)");
    CHECK(is(fpgfx_compare_exact(e, a, n - 1, w, h, &out), FPGFX_SIZE_MISMATCH, "len"),
          "compare one byte short");
    CHECK(is(fpgfx_compare_within(e, a, 0, w, h, 3, &out), FPGFX_SIZE_MISMATCH, "len"),
          "compare len 0");
    CHECK(is(fpgfx_compare_exact(e, a, SIZE_MAX, w, h, &out), FPGFX_SIZE_MISMATCH, "expected"),
          "compare len SIZE_MAX");
    /* width · height · 3 overflows 64 bits: the length cannot match. */
    CHECK(is(fpgfx_compare_exact(e, a, 3, UINT32_MAX, UINT32_MAX, &out), FPGFX_SIZE_MISMATCH,
             "len"), "compare UINT32_MAX x UINT32_MAX");
    CHECK(is(fpgfx_compare_exact(e, a, 0, 0, 0, &out), FPGFX_OK, "") && out.pixels == 0 &&
              out.failing == 0, "compare 0 x 0");
    for (unsigned tol = 0; tol < 256; tol += 5) {
        uint64_t failing;
        uint8_t max;
        recount(e, a, (size_t)w * h, (uint8_t)tol, &failing, &max);
        fpgfx_status st = tol ? fpgfx_compare_within(e, a, n, w, h, (uint8_t)tol, &out)
                              : fpgfx_compare_exact(e, a, n, w, h, &out);
        CHECK(is(st, FPGFX_OK, "") && out.pixels == (uint64_t)w * h &&
                  out.failing == failing && out.max_difference == max,
              "tolerance %u: %llu failing (want %llu), max %u (want %u)", tol,
              (unsigned long long)out.failing, (unsigned long long)failing,
              out.max_difference, max);
    }
    CHECK(is(fpgfx_compare_within(e, e, n, w, h, 0, &out), FPGFX_OK, "") && out.failing == 0,
          "a frame equals itself");
    free(e);
    free(a);
}

/* The sizing and rendering calls on one image of n words: NULL, short and long buffers
 * and bad start scalars, then a render in each number format (every_numeric) or in
 * F64, Q16.16 and Q32.32. */
static void render_image(const uint32_t *words, size_t n, int every_numeric) {
    uint32_t w = 0, h = 0;
    uint32_t *regs = block(n * sizeof(uint32_t));
    memcpy(regs, words, n * sizeof(uint32_t));
    fpgfx_status st = fpgfx_frame_size(regs, n, &w, &h);
    CHECK(documented(st), "frame_size");
    if (n != FPGFX_SCENE_WORDS) {
        CHECK(is(st, FPGFX_SIZE_MISMATCH, "n_regs"), "frame_size of %zu words", n);
        free(regs);
        return;
    }
    if (st != FPGFX_OK) {
        CHECK(is(st, FPGFX_BAD_REGISTERS, "regs: "), "frame_size refuses an image");
        free(regs);
        return;
    }
    CHECK(w >= 1 && w <= 4096 && h >= 1 && h <= 4096, "frame %ux%u", w, h);
    CHECK(is(fpgfx_frame_size(regs, n, NULL, &h), FPGFX_BAD_ARGUMENT, "width"),
          "frame_size(width NULL)");
    CHECK(is(fpgfx_frame_size(regs, n, &w, NULL), FPGFX_BAD_ARGUMENT, "height"),
          "frame_size(height NULL)");
    if ((size_t)w * h > 64) {
        /* The sizes only: a big frame is the golden model's business, not this harness's. */
        free(regs);
        return;
    }
    size_t px = (size_t)w * h;
    uint8_t *rgb = block(px * 3), *rgb_short = block(px * 3 - 1);
    float *depth = block(px * sizeof(float)), *normal = block(px * 3 * sizeof(float));
    fpgfx_start start = {FPGFX_NUMERIC_Q16_16, 1};
    CHECK(is(fpgfx_render(regs, n, NULL, 0, NULL, rgb, px * 3, NULL, 0, NULL, 0),
             FPGFX_BAD_ARGUMENT, "start"), "render(start NULL)");
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &start, rgb_short, px * 3 - 1, NULL, 0, NULL, 0),
             FPGFX_SIZE_MISMATCH, "out_len"), "render one byte short");
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &start, NULL, px * 3, NULL, 0, NULL, 0),
             FPGFX_BAD_ARGUMENT, "rgb888_out"), "render(rgb888_out NULL)");
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &start, rgb, px * 3, depth, px - 1, NULL, 0),
             FPGFX_SIZE_MISMATCH, "depth_out"), "render depth one short");
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &start, rgb, px * 3, NULL, 0, normal, px * 3 + 1),
             FPGFX_SIZE_MISMATCH, "normal_out"), "render normal one long");
    CHECK(is(fpgfx_render(regs, n, NULL, 1, &start, rgb, px * 3, NULL, 0, NULL, 0),
             FPGFX_BAD_ARGUMENT, "texture"), "render(texture NULL, 1)");
    CHECK(is(fpgfx_render(regs, n, rgb, px * 3, &start, rgb, px * 3, NULL, 0, NULL, 0),
             FPGFX_SIZE_MISMATCH, "tex_len"), "render with a short texture");
    fpgfx_start bad = {7, 0};
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &bad, rgb, px * 3, NULL, 0, NULL, 0),
             FPGFX_BAD_ARGUMENT, "start->numeric"), "numeric 7");
    bad.numeric = FPGFX_NUMERIC_F32;
    bad.aovs = 2;
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &bad, rgb, px * 3, NULL, 0, NULL, 0),
             FPGFX_BAD_ARGUMENT, "start->aovs"), "aovs 2");
    bad.aovs = 0;
    CHECK(is(fpgfx_render(regs, n, NULL, 0, &bad, rgb, px * 3, depth, px, NULL, 0),
             FPGFX_BAD_ARGUMENT, "depth_out"), "a depth plane without aovs");
    for (uint32_t num = 0; num <= FPGFX_NUMERIC_Q32_32; num += every_numeric ? 1 : 3) {
        start.numeric = num;
        st = fpgfx_render(regs, n, NULL, 0, &start, rgb, px * 3, depth, px, normal, px * 3);
        CHECK(documented(st) && (st == FPGFX_OK || st == FPGFX_DEVICE_ERROR),
              "render numeric %u: %d", (unsigned)num, (int)st);
    }
    free(rgb);
    free(rgb_short);
    free(depth);
    free(normal);
    free(regs);
}

static void image_calls(void) {
    uint32_t w, h;
    uint32_t *regs = block(FPGFX_SCENE_WORDS * sizeof(uint32_t));
    memset(regs, 0, FPGFX_SCENE_WORDS * sizeof(uint32_t));
    CHECK(is(fpgfx_frame_size(NULL, FPGFX_SCENE_WORDS, &w, &h), FPGFX_BAD_ARGUMENT, "regs"),
          "frame_size(regs NULL)");
    CHECK(is(fpgfx_frame_size(regs, FPGFX_SCENE_WORDS, NULL, &h), FPGFX_BAD_REGISTERS, "regs"),
          "frame_size(width NULL) on a zero image: regs first");
    CHECK(is(fpgfx_frame_size((const uint32_t *)((const char *)regs + 2), 1, &w, &h),
             FPGFX_BAD_ARGUMENT, "regs"), "frame_size(regs misaligned)");
    CHECK(is(fpgfx_frame_size(regs, FPGFX_SCENE_WORDS - 1, &w, &h), FPGFX_SIZE_MISMATCH,
             "n_regs"), "frame_size one word short");
    CHECK(is(fpgfx_frame_size(regs, SIZE_MAX, &w, &h), FPGFX_SIZE_MISMATCH, "regs"),
          "frame_size SIZE_MAX words");
    CHECK(is(fpgfx_frame_size(regs, FPGFX_SCENE_WORDS, &w, &h), FPGFX_BAD_REGISTERS, "regs: "),
          "an all-zero image");
    free(regs);
}

/* A valid image with one word at a time set to 0, 1, 0x7fffffff and 0xffffffff: every
 * field's codes, counts and reals out of range in turn. */
static void damaged_images(const uint32_t *words) {
    static const uint32_t values[] = {0, 1, 0x7fffffffu, 0xffffffffu};
    uint32_t *copy = block(FPGFX_SCENE_WORDS * sizeof(uint32_t));
    for (size_t k = 0; k < FPGFX_SCENE_WORDS; k++) {
        for (size_t v = 0; v < sizeof values / sizeof values[0]; v++) {
            memcpy(copy, words, FPGFX_SCENE_WORDS * sizeof(uint32_t));
            copy[k] = values[v];
            /* Keep the frame small: words 4 and 5 are width and height, 12 is spp. */
            if ((k == 4 || k == 5 || k == 12) && values[v] > 8) continue;
            render_image(copy, FPGFX_SCENE_WORDS, 0);
        }
    }
    free(copy);
}

/* Each FILE's bytes as a register image: as they are (any length), padded with zeros or
 * cut to FPGFX_SCENE_WORDS words; a FILE that is a whole image is also damaged word by
 * word. */
static void file_images(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        CHECK(0, "cannot open %s", path);
        return;
    }
    size_t cap = 4 * FPGFX_SCENE_WORDS + 64, len = 0;
    uint8_t *bytes = block(cap);
    len = fread(bytes, 1, cap, f);
    fclose(f);
    size_t n = len / 4;
    uint32_t *words = block((n ? n : 1) * sizeof(uint32_t));
    memcpy(words, bytes, n * sizeof(uint32_t));
    render_image(words, n, 1);
    uint32_t *full = block(FPGFX_SCENE_WORDS * sizeof(uint32_t));
    memset(full, 0, FPGFX_SCENE_WORDS * sizeof(uint32_t));
    memcpy(full, words, (n < FPGFX_SCENE_WORDS ? n : FPGFX_SCENE_WORDS) * sizeof(uint32_t));
    render_image(full, FPGFX_SCENE_WORDS, 1);
    if (n == FPGFX_SCENE_WORDS) damaged_images(full);
    free(words);
    free(full);
    free(bytes);
}

int main(int argc, char **argv) {
    raster_calls();
    compare_calls();
    image_calls();
    for (int i = 1; i < argc; i++) {
        file_images(argv[i]);
    }
    printf("%u passed, %u failed\n", passed, failed);
    return failed ? 1 : 0;
}
