// The C ABI over the Verilated core: `rt_math_top` (every arithmetic unit side by side),
// `rt_isect` (the intersection unit), `rt_cast` (the frame core) and `rt_device` (the
// core behind its AXI4-Lite slave), each one call per clock cycle (inputs in, outputs
// out), so the Rust side pays one FFI crossing per cycle. Built with VM_TRACE (the crate's
// `trace` feature), a model can also write a VCD of every signal, for the replay of a
// failing differential case; without it `rt_*_trace` refuses.

#include <cstdint>
#include <memory>

#include "Vrt_cast.h"
#include "Vrt_device.h"
#include "Vrt_isect.h"
#include "Vrt_math_top.h"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

// One Verilated top with its own context, and its waveform once one is asked for (each
// clock is two time steps: low, then high).
template <typename V>
struct Model {
    std::unique_ptr<VerilatedContext> ctx;
    std::unique_ptr<V> top;
    uint64_t time = 0;
#if VM_TRACE
    std::unique_ptr<VerilatedVcdC> vcd;
    ~Model() {
        if (vcd) vcd->close();
    }
#endif
};

struct RtMath : Model<Vrt_math_top> {};
struct RtIsect : Model<Vrt_isect> {};
struct RtCast : Model<Vrt_cast> {};
struct RtDevice : Model<Vrt_device> {};

// Frees a model. Verilator's scopes unregister from the thread's current context (the one
// made last on the thread), not from their own: with another model made and freed since,
// that pointer dangles and the free hangs on its mutex, so the model's own is made current.
template <typename M>
static void destroy(M* m) {
    if (!m) return;
    Verilated::threadContextp(m->ctx.get());
    delete m;
}

// The waveform's next time step, after an eval.
template <typename M>
static void dump(M* m) {
#if VM_TRACE
    if (m->vcd) m->vcd->dump(m->time);
#endif
    m->time++;
}

template <typename M>
static void edge(M* m) {
    m->top->clk = 0;
    m->top->eval();
    dump(m);
    m->top->clk = 1;
    m->top->eval();
    dump(m);
}

// Starts a VCD of every signal at `path` from the next clock on; 0 when the model is built
// without tracing, one is already open, or the file cannot be opened.
template <typename M>
static int trace(M* m, const char* path) {
#if VM_TRACE
    if (m->vcd) return 0;
    Verilated::threadContextp(m->ctx.get());
    auto vcd = std::make_unique<VerilatedVcdC>();
    m->top->trace(vcd.get(), 99);
    vcd->open(path);
    if (!vcd->isOpen()) return 0;
    m->vcd = std::move(vcd);
    return 1;
#else
    (void)m;
    (void)path;
    return 0;
#endif
}

// A model after 4 cycles of reset with its other inputs idle (`idle` sets them), or null
// when construction failed. `seed` 0 starts every register and memory at 0; any other
// seed starts them at random values drawn from it (Verilated with --x-initial unique),
// which the reset then has to bring to a known state wherever it matters.
template <typename M, typename V, typename Idle>
static M* make(Idle idle, uint64_t seed = 0) {
    auto* m = new (std::nothrow) M;
    if (!m) return nullptr;
    m->ctx = std::make_unique<VerilatedContext>();
#if VM_TRACE
    // tracing must be allowed before the model exists; it costs nothing until opened
    m->ctx->traceEverOn(true);
#endif
    if (seed != 0) {
        m->ctx->randReset(2);
        m->ctx->randSeed(static_cast<int>(seed & 0x7fffffff));
    }
    m->top = std::make_unique<V>(m->ctx.get());
    m->top->rst = 1;
    idle(*m->top);
    for (int i = 0; i < 4; i++) edge(m);
    m->top->rst = 0;
    return m;
}

// The arithmetic and intersection tops: clock enable high, no valid input.
template <typename V>
static void no_input(V& t) {
    t.ce = 1;
    t.in_valid = 0;
}

extern "C" {

RtMath* rt_math_new() { return make<RtMath, Vrt_math_top>(no_input<Vrt_math_top>); }

void rt_math_free(RtMath* m) { destroy(m); }

int rt_math_trace(RtMath* m, const char* path) { return trace(m, path); }

// in: valid, a0, a1, a2, b0, b1, b2, ce. out: for mul, mul_rn, dot2, dot3, div, sqrt,
// rsqrt, to_f32 in that order, (valid, y, sat) after the rising edge (sqrt's and to_f32's
// sat are 0).
void rt_math_cycle(RtMath* m, const uint32_t* in, uint32_t* out) {
    Vrt_math_top& t = *m->top;
    t.in_valid = in[0] != 0;
    t.a0 = in[1];
    t.a1 = in[2];
    t.a2 = in[3];
    t.b0 = in[4];
    t.b1 = in[5];
    t.b2 = in[6];
    t.ce = in[7] != 0;
    edge(m);
    const uint32_t o[24] = {
        t.mul_v,    t.mul_y,    t.mul_sat,    t.mul_rn_v, t.mul_rn_y, t.mul_rn_sat,
        t.dot2_v,   t.dot2_y,   t.dot2_sat,   t.dot3_v,   t.dot3_y,   t.dot3_sat,
        t.div_v,    t.div_y,    t.div_sat,    t.sqrt_v,   t.sqrt_y,   0,
        t.rsqrt_v,  t.rsqrt_y,  t.rsqrt_sat,  t.tof32_v,  t.tof32_y,  0,
    };
    for (int i = 0; i < 24; i++) out[i] = o[i];
}

RtIsect* rt_isect_new() { return make<RtIsect, Vrt_isect>(no_input<Vrt_isect>); }

void rt_isect_free(RtIsect* m) { destroy(m); }

int rt_isect_trace(RtIsect* m, const char* path) { return trace(m, path); }

// in: valid, shape, ox, oy, oz, dx, dy, dz, tmin, tmax, tag, ce. out: valid, hit, t,
// unsupported, tag after the rising edge.
void rt_isect_cycle(RtIsect* m, const uint32_t* in, uint32_t* out) {
    Vrt_isect& t = *m->top;
    t.in_valid = in[0] != 0;
    t.shape = in[1];
    t.ox = in[2];
    t.oy = in[3];
    t.oz = in[4];
    t.dx = in[5];
    t.dy = in[6];
    t.dz = in[7];
    t.tmin = in[8];
    t.tmax = in[9];
    t.tag = in[10];
    t.ce = in[11] != 0;
    edge(m);
    out[0] = t.out_valid;
    out[1] = t.hit;
    out[2] = t.t;
    out[3] = t.unsupported;
    out[4] = t.tag_out;
}

RtCast* rt_cast_new(uint64_t seed) {
    return make<RtCast, Vrt_cast>(
        [](Vrt_cast& t) {
            t.hold = 0;
            t.start = 0;
            t.cfg_we = 0;
        },
        seed);
}

void rt_cast_free(RtCast* m) { destroy(m); }

int rt_cast_trace(RtCast* m, const char* path) { return trace(m, path); }

// One clock. in: cfg_we, cfg_addr, cfg_data, start, hold. out: busy, done, err,
// pix_valid, pix_x, pix_y, pix_hit, pix_obj, pix_t, pix_n x, y, z, pix_rgb, pix_kcu116
// after the rising edge.
void rt_cast_cycle(RtCast* m, const uint32_t* in, uint32_t* out) {
    Vrt_cast& t = *m->top;
    t.cfg_we = in[0] != 0;
    t.cfg_addr = in[1];
    t.cfg_data = in[2];
    t.start = in[3] != 0;
    t.hold = in[4] != 0;
    edge(m);
    out[0] = t.busy;
    out[1] = t.done;
    out[2] = t.err;
    out[3] = t.pix_valid;
    out[4] = t.pix_x;
    out[5] = t.pix_y;
    out[6] = t.pix_hit;
    out[7] = t.pix_obj;
    out[8] = t.pix_t;
    out[9] = t.pix_n[0];
    out[10] = t.pix_n[1];
    out[11] = t.pix_n[2];
    out[12] = t.pix_rgb;
    out[13] = t.pix_kcu116;
}

RtDevice* rt_device_new() {
    return make<RtDevice, Vrt_device>([](Vrt_device& t) {
        t.s_axi_awvalid = 0;
        t.s_axi_wvalid = 0;
        t.s_axi_bready = 0;
        t.s_axi_arvalid = 0;
        t.s_axi_rready = 0;
        t.s_axi_awprot = 0;
        t.s_axi_arprot = 0;
        t.mem_ready = 1;
        t.rd_ready = 1;
        t.rd_resp = 0;
    });
}

void rt_device_free(RtDevice* m) { destroy(m); }

int rt_device_trace(RtDevice* m, const char* path) { return trace(m, path); }

// One clock. in: awvalid, awaddr, wvalid, wdata, wstrb, bready, arvalid, araddr, rready,
// mem_ready, rd_ready, rd_resp, rd_rgb, rd_obj, rd_t, rd_n x, y, z. out, sampled before
// the rising edge (what the master and the memory see when they decide): awready,
// wready, bvalid, bresp, arready, rvalid, rdata, rresp, irq, mem_valid, mem_index,
// mem_rgb, mem_kcu116, mem_obj, mem_t, mem_n x, y, z, mem_aovs, rd_valid, rd_index.
void rt_device_cycle(RtDevice* m, const uint32_t* in, uint32_t* out) {
    Vrt_device& t = *m->top;
    t.s_axi_awvalid = in[0] != 0;
    t.s_axi_awaddr = in[1];
    t.s_axi_wvalid = in[2] != 0;
    t.s_axi_wdata = in[3];
    t.s_axi_wstrb = in[4];
    t.s_axi_bready = in[5] != 0;
    t.s_axi_arvalid = in[6] != 0;
    t.s_axi_araddr = in[7];
    t.s_axi_rready = in[8] != 0;
    t.mem_ready = in[9] != 0;
    t.rd_ready = in[10] != 0;
    t.rd_resp = in[11] != 0;
    t.rd_rgb = in[12];
    t.rd_obj = in[13];
    t.rd_t = in[14];
    t.rd_n[0] = in[15];
    t.rd_n[1] = in[16];
    t.rd_n[2] = in[17];
    t.clk = 0;
    t.eval();
    dump(m);
    const uint32_t o[21] = {
        t.s_axi_awready, t.s_axi_wready, t.s_axi_bvalid, t.s_axi_bresp, t.s_axi_arready,
        t.s_axi_rvalid,  t.s_axi_rdata,  t.s_axi_rresp,  t.irq,         t.mem_valid,
        t.mem_index,     t.mem_rgb,      t.mem_kcu116,   t.mem_obj,     t.mem_t,
        t.mem_n[0],      t.mem_n[1],     t.mem_n[2],     t.mem_aovs,    t.rd_valid,
        t.rd_index,
    };
    for (int i = 0; i < 21; i++) out[i] = o[i];
    t.clk = 1;
    t.eval();
    dump(m);
}

}  // extern "C"
