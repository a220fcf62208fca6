# Google Benchmark of the rheometer (cases/mpm/rheometer_test1.yaml: multi-regime material on the
# polar grid, double-point MPM), a fixed number of steps, 1 and 2 threads.
# Figures and the command: docs/performance.md#rheometer_bench.
if(TARGET granflow_mpm_kind)
  add_executable(bench_rheometer ${CMAKE_CURRENT_LIST_DIR}/bench_rheometer.cpp)
  target_link_libraries(bench_rheometer PRIVATE granflow_mpm_kind benchmark::benchmark)
  target_compile_definitions(bench_rheometer PRIVATE GRANFLOW_SOURCE_DIR="${GRANFLOW_SOURCE_DIR}")
endif()
