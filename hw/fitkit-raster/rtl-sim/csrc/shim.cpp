// The C ABI over the Verilated `fitkit_sim_top`: one call per clock cycle (inputs in,
// outputs out) so the Rust side pays one FFI crossing per cycle, and the framebuffer
// RAM found by its shape in Verilator's public-signal table, so the Rust side does not
// depend on the RTL's instance names.

#include <cstdint>
#include <cstring>
#include <memory>

#include "Vfitkit_sim_top.h"
#include "Vfitkit_sim_top8.h"
#include "Vfitkit_sim_top_line.h"
#include "Vfitkit_sim_top_tri.h"
#include "verilated.h"
#include "verilated_syms.h"
#include "verilated_vcd_c.h"

namespace {
constexpr size_t kRamBytes = size_t{1} << 18;

enum : uint32_t {
    IN_RST = 1u << 0,
    IN_SCK = 1u << 1,
    IN_CS_N = 1u << 2,
    IN_MOSI = 1u << 3,
    IN_MEM_WAIT = 1u << 4,
    // The clock is stopped: a tick evaluates the inputs but no edge (a stuck block).
    IN_CLOCK_GATED = 1u << 5,
};

enum : uint32_t {
    OUT_MISO = 1u << 0,
    OUT_FIFO_FREE = 1u << 1,
    OUT_BUSY = 1u << 2,
};
}  // namespace

// One of the Verilated builds (the seed's, TRI_LANES = 8, line-only, triangle-only) behind
// one interface: all have the same pins, and the Rust side picks the build when it makes
// the model.
struct Top {
    virtual ~Top() = default;
    virtual void apply(uint32_t in) = 0;
    virtual uint32_t outputs() const = 0;
    virtual void set_clk(bool high) = 0;
    virtual void eval() = 0;
    virtual void trace(VerilatedVcdC* vcd) = 0;
    virtual void final() = 0;
};

template <class V>
struct TopOf final : Top {
    std::unique_ptr<V> v;
    TopOf(VerilatedContext* ctx, const char* name) : v(std::make_unique<V>(ctx, name)) {}
    void apply(uint32_t in) override {
        v->rst = (in & IN_RST) != 0;
        v->spi_sck = (in & IN_SCK) != 0;
        v->spi_cs_n = (in & IN_CS_N) != 0;
        v->spi_mosi = (in & IN_MOSI) != 0;
        v->mem_wait = (in & IN_MEM_WAIT) != 0;
    }
    uint32_t outputs() const override {
        return (v->spi_miso ? OUT_MISO : 0) | (v->fifo_free ? OUT_FIFO_FREE : 0) |
               (v->busy ? OUT_BUSY : 0);
    }
    void set_clk(bool high) override { v->clk = high; }
    void eval() override { v->eval(); }
    void trace(VerilatedVcdC* vcd) override { v->trace(vcd, 99); }
    void final() override { v->final(); }
};

struct FitkitRtl {
    std::unique_ptr<VerilatedContext> ctx;
    std::unique_ptr<Top> top;
    uint8_t* ram = nullptr;
    // The waveform, once a failing case asks for one; each tick is two time steps.
    std::unique_ptr<VerilatedVcdC> vcd;
    uint64_t time = 0;
};

// The one public unpacked array of 2^18 bytes: the sim top's framebuffer RAM.
static uint8_t* find_ram(VerilatedContext* ctx) {
    uint8_t* found = nullptr;
    const VerilatedScopeNameMap* scopes = ctx->scopeNameMap();
    if (!scopes) return nullptr;
    for (const auto& s : *scopes) {
        const VerilatedVarNameMap* vars = s.second->varsp();
        if (!vars) continue;
        for (const auto& v : *vars) {
            const VerilatedVar& var = v.second;
            if (var.vltype() == VLVT_UINT8 && var.udims() == 1 &&
                var.totalSize() == kRamBytes) {
                if (found) return nullptr;  // ambiguous
                found = static_cast<uint8_t*>(var.datap());
            }
        }
    }
    return found;
}

extern "C" {

// A model in reset-released idle state, or null when no RAM is visible (`*no_ram` set)
// or construction failed. `seed` 0 starts every register and memory at 0; any other seed
// starts them at random values drawn from it (Verilated with --x-initial unique), so a
// test can show that nothing uninitialised reaches an output.
// `build` picks the Verilated top, in the order of the Rust side's `Build::ALL`: 0
// fitkit_sim_top, 1 fitkit_sim_top8, 2 fitkit_sim_top_line, 3 fitkit_sim_top_tri; any
// other value gives null without `*no_ram`.
FitkitRtl* fitkit_rtl_new(int* no_ram, uint64_t seed, uint32_t build) {
    *no_ram = 0;
    auto* m = new (std::nothrow) FitkitRtl;
    if (!m) return nullptr;
    m->ctx = std::make_unique<VerilatedContext>();
    if (seed != 0) {
        m->ctx->randReset(2);
        m->ctx->randSeed(static_cast<int>(seed & 0x7fffffff));
    }
    // tracing must be allowed before the model exists; it costs nothing until opened
    m->ctx->traceEverOn(true);
    switch (build) {
        case 0:
            m->top = std::make_unique<TopOf<Vfitkit_sim_top>>(m->ctx.get(), "fitkit_sim_top");
            break;
        case 1:
            m->top = std::make_unique<TopOf<Vfitkit_sim_top8>>(m->ctx.get(), "fitkit_sim_top8");
            break;
        case 2:
            m->top = std::make_unique<TopOf<Vfitkit_sim_top_line>>(m->ctx.get(),
                                                                   "fitkit_sim_top_line");
            break;
        case 3:
            m->top = std::make_unique<TopOf<Vfitkit_sim_top_tri>>(m->ctx.get(),
                                                                  "fitkit_sim_top_tri");
            break;
        default:
            delete m;
            return nullptr;
    }
    m->ram = find_ram(m->ctx.get());
    if (!m->ram) {
        *no_ram = 1;
        delete m;
        return nullptr;
    }
    m->top->set_clk(false);
    m->top->apply(IN_CS_N);
    m->top->eval();
    return m;
}

void fitkit_rtl_free(FitkitRtl* m) {
    if (!m) return;
    if (m->vcd) m->vcd->close();
    m->top->final();
    delete m;
}

// Starts a VCD of every signal at `path` from the next tick on; 0 when it cannot be
// opened (or one is already open).
int fitkit_rtl_trace(FitkitRtl* m, const char* path) {
    if (m->vcd) return 0;
    auto vcd = std::make_unique<VerilatedVcdC>();
    m->top->trace(vcd.get());
    vcd->open(path);
    if (!vcd->isOpen()) return 0;
    m->vcd = std::move(vcd);
    return 1;
}

// Applies `in`, lets combinational logic settle, and returns the outputs.
uint32_t fitkit_rtl_set(FitkitRtl* m, uint32_t in) {
    m->top->apply(in);
    m->top->eval();
    return m->top->outputs();
}

// One clock cycle with `in` held (rising edge, then falling edge); returns the outputs
// after it. A gated clock leaves the model untouched.
uint32_t fitkit_rtl_tick(FitkitRtl* m, uint32_t in) {
    m->top->apply(in);
    if (in & IN_CLOCK_GATED) {
        m->top->eval();
        return m->top->outputs();
    }
    m->top->set_clk(true);
    m->top->eval();
    if (m->vcd) m->vcd->dump(m->time);
    m->top->set_clk(false);
    m->top->eval();
    if (m->vcd) m->vcd->dump(m->time + 1);
    m->time += 2;
    return m->top->outputs();
}

const uint8_t* fitkit_rtl_ram(const FitkitRtl* m, size_t* len) {
    *len = kRamBytes;
    return m->ram;
}

}  // extern "C"
