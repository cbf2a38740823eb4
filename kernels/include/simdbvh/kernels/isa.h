#pragma once
// Instruction-set selection: detected once from CPUID/XGETBV, overridable with
// SIMDBVH_ISA=scalar|avx2|avx512 or set_active_isa().
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

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
// The ISA set_active_isa() or a non-empty SIMDBVH_ISA forces, if any (entry
// points that choose their ISA by speed, e.g. the wide BVH traversal, obey it).
std::optional<Isa> forced_isa();
// Throws simdbvh::Error with a clear message when the CPU lacks the ISA.
void require(Isa isa);

// The best ISA this CPU and OS support (ignores SIMDBVH_ISA and set_active_isa()).
Isa detected_isa();
// Every supported ISA, in kAllIsas order.
std::vector<Isa> supported_isas();
// The ISA a SIMDBVH_ISA value asks for: empty -> detected_isa(); throws
// simdbvh::Error for an unknown name or an ISA this CPU lacks.
Isa isa_from_request(std::string_view request);
// The same against a given set of available ISAs (best = the last one listed).
Isa isa_from_request(std::string_view request, std::span<const Isa> available);
// The CPU brand string (CPUID 0x80000002..4), trimmed; "unknown" if absent.
std::string_view cpu_name();

}  // namespace simdbvh
