# Sourced by scripts/asan.sh and scripts/tsan.sh: which SIMD ISA's objects a
# sanitizer build instruments on a CPU with AVX-512F (SIMDBVH_SANITIZE_SIMD_ISA,
# cmake/SimdbvhIsa.cmake; the avx2 and avx512 objects instantiate the same
# templates, so one of them per run, by turns, checks both over two runs).
#   sanitize_simd_isa TURN
# prints SANITIZE_SIMD_ISA when set (all|avx2|avx512), else avx512 for an even
# TURN and avx2 for an odd one, and all when TURN is empty (no git history).
sanitize_simd_isa() {
  if [ -n "${SANITIZE_SIMD_ISA:-}" ]; then
    echo "$SANITIZE_SIMD_ISA"
  elif [ -z "${1:-}" ]; then
    echo all
  elif [ $(( $1 % 2 )) -eq 0 ]; then
    echo avx512
  else
    echo avx2
  fi
}
