# Google Benchmark of one full collisional + liquid closure evaluation (continuum/model/).
# Uses CMAKE_CURRENT_LIST_DIR so that it works when included from bench/CMakeLists.txt.
add_executable(bench_closures ${CMAKE_CURRENT_LIST_DIR}/bench_closures.cpp)
target_link_libraries(bench_closures PRIVATE granflow_model benchmark::benchmark)
