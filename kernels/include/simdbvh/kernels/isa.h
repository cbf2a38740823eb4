#pragma once
// Instruction-set selection: detected once from CPUID/XGETBV, overridable with
// SIMDBVH_ISA=scalar|avx2|avx512 or set_active_isa().
#include <cstdint>
#include <optional>
#include <string_view>

namespace simdbvh {

enum class Isa : std::uint8_t { scalar = 0, avx2 = 1, avx512 = 2 };

inline constexpr Isa kAllIsas[] = {Isa::scalar, Isa::avx2, Isa::avx512};

std::string_view name(Isa isa);
std::optional<Isa> parse_isa(std::string_view s);

// True when this CPU and OS can run the ISA's code path.
bool supported(Isa isa);
// The best supported ISA, or the one forced by SIMDBVH_ISA / set_active_isa().
// Throws simdbvh::Error when SIMDBVH_ISA names an unknown or unsupported ISA.
Isa active_isa();
// Forces the active ISA; throws simdbvh::Error when the CPU lacks it.
void set_active_isa(Isa isa);
// Throws simdbvh::Error with a clear message when the CPU lacks the ISA.
void require(Isa isa);

}  // namespace simdbvh
