# simdbvh_bench_traversal: BVH2, BVH4/8/16 (per ISA) and Embree traversal side by side,
# from bench/bvh2/*_bench.cpp, bench/bvh8/*_bench.cpp, bench/query/*_bench.cpp and bench/reference/*_bench.cpp. Included by
# bench/CMakeLists.txt.
file(GLOB _traversal_bench_srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/bvh2/*_bench.cpp
     ${CMAKE_CURRENT_LIST_DIR}/bvh8/*_bench.cpp ${CMAKE_CURRENT_LIST_DIR}/query/*_bench.cpp
     ${CMAKE_CURRENT_LIST_DIR}/reference/*_bench.cpp)
if(_traversal_bench_srcs)
  add_executable(simdbvh_bench_traversal ${_traversal_bench_srcs} ${CMAKE_CURRENT_LIST_DIR}/bvh8/traversal_fixture.cpp)
  target_include_directories(simdbvh_bench_traversal PRIVATE ${CMAKE_CURRENT_LIST_DIR}/bvh8 ${CMAKE_CURRENT_LIST_DIR}/query)
  # simdbvh_bvh8_internal: isa_choice.h (the calibrating batch's benchmark forgets the choice).
  target_link_libraries(simdbvh_bench_traversal PRIVATE simdbvh_workloads simdbvh_bvh8 simdbvh_bvh8_internal
                        simdbvh_reference benchmark::benchmark)
endif()
