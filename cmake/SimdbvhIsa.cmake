# Per-ISA compile flags, applied per source file: src/scalar/*.cpp get none
# (baseline x86-64, no AVX), src/avx2/*.cpp AVX2+FMA, src/avx512/*.cpp AVX-512.
# One binary runs everywhere and picks its path at runtime; never -march=native.
set(SIMDBVH_AVX2_FLAGS -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt -mf16c)
set(SIMDBVH_AVX512_FLAGS ${SIMDBVH_AVX2_FLAGS} -mavx512f -mavx512vl -mavx512dq -mavx512bw -mavx512cd)

# SIMDBVH_SANITIZE_HOST_ISAS_ONLY (on in the asan and tsan presets): on a machine without
# AVX-512F, the src/avx512/ objects are compiled without sanitizer
# instrumentation (same -O level). Their code never runs there (kernels/src/isa.cpp
# picks AVX-512 only when the CPU has F, VL, DQ, BW and CD), so instrumenting
# it only costs build time: under the asan preset bvh8's traverse_avx512.cpp
# takes 137 s of CPU instrumented, the most of any file. On a machine with
# AVX-512F everything stays instrumented.
option(SIMDBVH_SANITIZE_HOST_ISAS_ONLY "Sanitized builds: no instrumentation for ISAs this CPU lacks" OFF)
if(SIMDBVH_SANITIZE_HOST_ISAS_ONLY AND EXISTS /proc/cpuinfo)
  file(STRINGS /proc/cpuinfo _simdbvh_cpu_flags REGEX "^flags" LIMIT_COUNT 1)
  if(NOT _simdbvh_cpu_flags MATCHES "[ \t]avx512f([ \t]|$)")
    message(STATUS "simdbvh: no AVX-512F on this CPU: src/avx512/ objects compiled without sanitizers")
    list(APPEND SIMDBVH_AVX512_FLAGS -fno-sanitize=all)
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
