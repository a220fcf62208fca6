# Google Benchmark of the double-point MPM on the fixed problems MPM-1 (elastic column, single
# phase) and MPM-2 (consolidation column, two phase) of docs/performance.md (section MPM), 1 and 2 threads.
# Figures and the command: docs/performance.md#mpm.
if(TARGET granflow_mpm)
  add_executable(bench_mpm ${CMAKE_CURRENT_LIST_DIR}/bench_mpm.cpp)
  target_link_libraries(bench_mpm PRIVATE granflow_mpm benchmark::benchmark)
endif()
