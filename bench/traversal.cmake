# simdbvh_bench_traversal: BVH2 and BVH8 (per ISA) traversal side by side,
# from bench/bvh2/*_bench.cpp and bench/bvh8/*_bench.cpp. Included by
# bench/CMakeLists.txt.
file(GLOB _traversal_bench_srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/bvh2/*_bench.cpp
     ${CMAKE_CURRENT_LIST_DIR}/bvh8/*_bench.cpp)
if(_traversal_bench_srcs)
  add_executable(simdbvh_bench_traversal ${_traversal_bench_srcs} ${CMAKE_CURRENT_LIST_DIR}/bvh8/traversal_fixture.cpp)
  target_include_directories(simdbvh_bench_traversal PRIVATE ${CMAKE_CURRENT_LIST_DIR}/bvh8)
  target_link_libraries(simdbvh_bench_traversal PRIVATE simdbvh_scene simdbvh_bvh8 benchmark::benchmark)
endif()
