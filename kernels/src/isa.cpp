// CPU detection: CPUID for the instruction sets, XGETBV for the register
// state the OS saves (YMM: XCR0 bits 1-2; AVX-512: also opmask/ZMM bits 5-7).
// Compiled for baseline x86-64: this code must run on any CPU. On any other
// processor no x86 path is built (cmake/SimdbvhIsa.cmake) and only scalar is
// supported.
#include "simdbvh/kernels/isa.h"

#if defined(__x86_64__)
#include <cpuid.h>
#endif

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "simdbvh/kernels/error.h"

namespace simdbvh {
namespace {

struct CpuInfo {
    bool avx2 = false;
    bool avx512 = false;
    std::string brand = "unknown";
};

#if defined(__x86_64__)
std::uint64_t xgetbv0() {
    std::uint32_t eax, edx;
    asm volatile(".byte 0x0f, 0x01, 0xd0" : "=a"(eax), "=d"(edx) : "c"(0));  // xgetbv, no -mxsave needed
    return (std::uint64_t(edx) << 32) | eax;
}

bool bit(std::uint32_t reg, int i) { return (reg >> i) & 1u; }

CpuInfo detect() {
    CpuInfo info;
    unsigned a = 0, b = 0, c = 0, d = 0;
    const unsigned max_leaf = __get_cpuid_max(0, nullptr);
    const unsigned max_ext = __get_cpuid_max(0x80000000u, nullptr);
    if (max_ext >= 0x80000004u) {
        char s[49] = {};
        for (unsigned i = 0; i < 3; ++i) {
            __get_cpuid(0x80000002u + i, &a, &b, &c, &d);
            const unsigned r[4] = {a, b, c, d};
            for (int k = 0; k < 16; ++k) s[16 * i + k] = static_cast<char>((r[k / 4] >> (8 * (k % 4))) & 0xff);
        }
        std::string brand(s);
        const auto first = brand.find_first_not_of(' ');
        const auto last = brand.find_last_not_of(' ');
        if (first != std::string::npos) info.brand = brand.substr(first, last - first + 1);
    }
    if (max_leaf < 7) return info;
    __get_cpuid(1, &a, &b, &c, &d);
    const bool fma = bit(c, 12), popcnt = bit(c, 23), osxsave = bit(c, 27), avx = bit(c, 28), f16c = bit(c, 29);
    __get_cpuid_count(7, 0, &a, &b, &c, &d);
    const bool bmi1 = bit(b, 3), avx2 = bit(b, 5), bmi2 = bit(b, 8);
    const bool avx512f = bit(b, 16), avx512dq = bit(b, 17), avx512cd = bit(b, 28), avx512bw = bit(b, 30),
               avx512vl = bit(b, 31);
    bool lzcnt = false;
    if (max_ext >= 0x80000001u) {
        __get_cpuid(0x80000001u, &a, &b, &c, &d);
        lzcnt = bit(c, 5);  // ABM/LZCNT
    }
    if (!osxsave) return info;
    const std::uint64_t xcr0 = xgetbv0();
    const bool os_ymm = (xcr0 & 0x6) == 0x6;              // SSE + AVX state
    const bool os_zmm = os_ymm && (xcr0 & 0xe0) == 0xe0;  // opmask + ZMM_Hi256 + Hi16_ZMM
    // Exactly the flags src/avx2/ is compiled with (cmake/SimdbvhIsa.cmake).
    info.avx2 = os_ymm && avx && avx2 && fma && bmi1 && bmi2 && lzcnt && popcnt && f16c;
    info.avx512 = info.avx2 && os_zmm && avx512f && avx512vl && avx512dq && avx512bw && avx512cd;
    return info;
}
#else
CpuInfo detect() { return {}; }  // no x86 path is compiled for this processor
#endif

const CpuInfo& cpu() {
    static const CpuInfo info = detect();  // once, thread-safe
    return info;
}

// -1: not forced by set_active_isa().
std::atomic<int> g_forced{-1};

Isa env_isa() {
    static const Isa isa = [] {
        const char* env = std::getenv("SIMDBVH_ISA");
        return isa_from_request(env ? std::string_view(env) : std::string_view());
    }();  // throws (and retries on the next call) for a bad value
    return isa;
}

}  // namespace

std::string_view name(Isa isa) {
    constexpr std::string_view kNames[] = {"scalar", "avx2", "avx512"};  // in the order of enum Isa
    const auto i = std::size_t(isa);
    return i < std::size(kNames) ? kNames[i] : "unknown";
}

std::optional<Isa> parse_isa(std::string_view s) {
    for (Isa isa : kAllIsas)
        if (s == name(isa)) return isa;
    return std::nullopt;
}

bool supported(Isa isa) {
    const bool has[] = {true, cpu().avx2, cpu().avx512};  // in the order of enum Isa
    const auto i = std::size_t(isa);
    return i < std::size(has) && has[i];
}

Isa detected_isa() { return supported(Isa::avx512) ? Isa::avx512 : (supported(Isa::avx2) ? Isa::avx2 : Isa::scalar); }

std::vector<Isa> supported_isas() {
    std::vector<Isa> out;
    for (Isa isa : kAllIsas)
        if (supported(isa)) out.push_back(isa);
    return out;
}

void require(Isa isa) {
    if (supported(isa)) return;
    if (!parse_isa(name(isa))) throw Error("invalid ISA value " + std::to_string(int(isa)));
    throw Error("this CPU (" + std::string(cpu_name()) + ") or its OS does not support the " + std::string(name(isa)) +
                " code path; the best supported is " + std::string(name(detected_isa())));
}

Isa isa_from_request(std::string_view request, std::span<const Isa> available) {
    auto has = [&](Isa isa) {
        for (Isa a : available)
            if (a == isa) return true;
        return false;
    };
    const Isa best = available.empty() ? Isa::scalar : available.back();
    if (request.empty()) return best;
    const std::optional<Isa> isa = parse_isa(request);
    if (!isa) throw Error("SIMDBVH_ISA='" + std::string(request) + "' is not one of scalar, avx2, avx512");
    if (!has(*isa))
        throw Error("SIMDBVH_ISA=" + std::string(request) + " but this CPU (" + std::string(cpu_name()) +
                    ") or its OS lacks it; the best supported is " + std::string(name(best)));
    return *isa;
}

Isa isa_from_request(std::string_view request) {
    const std::vector<Isa> available = supported_isas();
    return isa_from_request(request, available);
}

Isa active_isa() {
    const int forced = g_forced.load(std::memory_order_relaxed);
    if (forced >= 0) return static_cast<Isa>(forced);
    return env_isa();
}

void set_active_isa(Isa isa) {
    require(isa);
    g_forced.store(static_cast<int>(isa), std::memory_order_relaxed);
}

std::optional<Isa> forced_isa() {
    const int forced = g_forced.load(std::memory_order_relaxed);
    if (forced >= 0) return static_cast<Isa>(forced);
    static const bool env_set = [] {  // read once: the single-ray entry points ask on every call
        const char* env = std::getenv("SIMDBVH_ISA");
        return env && *env;
    }();
    if (env_set) return env_isa();
    return std::nullopt;
}

std::string_view cpu_name() { return cpu().brand; }

}  // namespace simdbvh
