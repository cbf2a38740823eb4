# Per-ISA compile flags, applied per source file: src/scalar/*.cpp get none
# (baseline x86-64, no AVX), src/avx2/*.cpp AVX2+FMA, src/avx512/*.cpp AVX-512.
# One binary runs everywhere and picks its path at runtime; never -march=native.
set(SIMDBVH_AVX2_FLAGS -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt -mf16c)
set(SIMDBVH_AVX512_FLAGS ${SIMDBVH_AVX2_FLAGS} -mavx512f -mavx512vl -mavx512dq -mavx512bw -mavx512cd)

function(simdbvh_isa_flags)
  foreach(src IN LISTS ARGN)
    if(src MATCHES "/avx512/")
      set_source_files_properties(${src} PROPERTIES COMPILE_OPTIONS "${SIMDBVH_AVX512_FLAGS}")
    elseif(src MATCHES "/avx2/")
      set_source_files_properties(${src} PROPERTIES COMPILE_OPTIONS "${SIMDBVH_AVX2_FLAGS}")
    endif()
  endforeach()
endfunction()
