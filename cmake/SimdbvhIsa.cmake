# Per-ISA compile flags, applied per source file: src/scalar/*.cpp get none
# (baseline x86-64, no AVX), src/avx2/*.cpp AVX2+FMA, src/avx512/*.cpp AVX-512.
# One binary runs everywhere and picks its path at runtime; never -march=native.
# The x86 paths (src/avx2, src/avx512, CPUID) are built only for an x86-64
# target: on any other processor the rooms build src/scalar/ alone
# (simdbvh_isa_sources) and the scalar path is the only one.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64|x64)$")
  set(SIMDBVH_X86_64 ON)
else()
  set(SIMDBVH_X86_64 OFF)
endif()
message(STATUS "simdbvh: target processor ${CMAKE_SYSTEM_PROCESSOR}, x86 ISAs: ${SIMDBVH_X86_64}")
set(SIMDBVH_AVX2_FLAGS -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt -mf16c)
set(SIMDBVH_AVX512_FLAGS ${SIMDBVH_AVX2_FLAGS} -mavx512f -mavx512vl -mavx512dq -mavx512bw -mavx512cd)

# SIMDBVH_SANITIZE_HOST_ISAS_ONLY (on in the asan and tsan presets): on a machine without
# AVX-512F, the src/avx512/ objects are compiled without sanitizer
# instrumentation (same -O level). Their code never runs there (kernels/src/isa.cpp
# picks AVX-512 only when the CPU has F, VL, DQ, BW and CD), so instrumenting
# it only costs build time: under the asan preset bvh8's traverse_avx512.cpp
# takes 137 s of CPU instrumented, the most of any file. On a machine with
# AVX-512F, SIMDBVH_SANITIZE_SIMD_ISA below.
option(SIMDBVH_SANITIZE_HOST_ISAS_ONLY "Sanitized builds: no instrumentation for ISAs this CPU lacks" OFF)
# SIMDBVH_SANITIZE_SIMD_ISA (scripts/asan.sh and scripts/tsan.sh set it): all, or
# avx2 or avx512: on a CPU with AVX-512F, only that SIMD ISA's objects are
# instrumented, the other one's compiled without sanitizers. The two are
# instantiations of the same templates (traverse-inl.h, kernels/src/simd), so
# either checks the shared code; the scripts alternate them by commit count, so
# each ISA's objects run under each sanitizer every few commits on main. Without
# AVX-512F the AVX2 objects are always the instrumented ones (see above).
set(SIMDBVH_SANITIZE_SIMD_ISA "all" CACHE STRING "Sanitized builds on an AVX-512 CPU: all, avx2 or avx512")
set_property(CACHE SIMDBVH_SANITIZE_SIMD_ISA PROPERTY STRINGS all avx2 avx512)
if(NOT SIMDBVH_SANITIZE_SIMD_ISA MATCHES "^(all|avx2|avx512)$")
  message(FATAL_ERROR "SIMDBVH_SANITIZE_SIMD_ISA must be all, avx2 or avx512 (got '${SIMDBVH_SANITIZE_SIMD_ISA}')")
endif()
if(SIMDBVH_SANITIZE_HOST_ISAS_ONLY AND EXISTS /proc/cpuinfo)
  file(STRINGS /proc/cpuinfo _simdbvh_cpu_flags REGEX "^flags" LIMIT_COUNT 1)
  if(NOT _simdbvh_cpu_flags MATCHES "[ \t]avx512f([ \t]|$)")
    message(STATUS "simdbvh: no AVX-512F on this CPU: src/avx512/ objects compiled without sanitizers")
    list(APPEND SIMDBVH_AVX512_FLAGS -fno-sanitize=all)
  elseif(SIMDBVH_SANITIZE_SIMD_ISA STREQUAL "avx2")
    message(STATUS "simdbvh: SIMDBVH_SANITIZE_SIMD_ISA=avx2: src/avx512/ objects compiled without sanitizers")
    list(APPEND SIMDBVH_AVX512_FLAGS -fno-sanitize=all)
  elseif(SIMDBVH_SANITIZE_SIMD_ISA STREQUAL "avx512")
    message(STATUS "simdbvh: SIMDBVH_SANITIZE_SIMD_ISA=avx512: src/avx2/ objects compiled without sanitizers")
    list(APPEND SIMDBVH_AVX2_FLAGS -fno-sanitize=all)
  endif()
endif()

# SIMDBVH_TRAVERSAL_SANITIZE_FLAGS (the asan preset: -fno-sanitize=alignment,null,
# pointer-overflow,vptr): extra flags for the per-ISA traversal instantiations
# (src/<isa>/traverse_*.cpp, src/<isa>/shape_traverse_*.cpp), the four costliest
# files of the instrumented build. UBSan's per-dereference checks there cost
# more compile time than all the rest of their instrumentation (traverse_scalar:
# 55 s of CPU with them, 31-38 s without, 19 s uninstrumented), and ASan still
# checks every one of those loads and stores; the arithmetic checks (overflow,
# shifts, float-divide-by-zero, float-cast-overflow, bounds) stay on.
set(SIMDBVH_TRAVERSAL_SANITIZE_FLAGS "" CACHE STRING "Sanitized builds: extra flags for the per-ISA traversal files")

# Drops from the list <var> the per-ISA sources the target processor cannot run.
function(simdbvh_isa_sources var)
  set(kept "")
  foreach(src IN LISTS ${var})
    if(NOT SIMDBVH_X86_64 AND src MATCHES "/(avx2|avx512)/")
      continue()
    endif()
    list(APPEND kept ${src})
  endforeach()
  set(${var} ${kept} PARENT_SCOPE)
endfunction()

function(simdbvh_isa_flags)
  foreach(src IN LISTS ARGN)
    set(flags "")
    if(src MATCHES "/avx512/")
      set(flags ${SIMDBVH_AVX512_FLAGS})
    elseif(src MATCHES "/avx2/")
      set(flags ${SIMDBVH_AVX2_FLAGS})
    endif()
    if(SIMDBVH_TRAVERSAL_SANITIZE_FLAGS AND src MATCHES "/(scalar|avx2|avx512)/(shape_)?traverse_[a-z0-9]+\\.cpp$")
      list(APPEND flags ${SIMDBVH_TRAVERSAL_SANITIZE_FLAGS})
    endif()
    if(flags)
      set_source_files_properties(${src} PROPERTIES COMPILE_OPTIONS "${flags}")
    endif()
  endforeach()
endfunction()
