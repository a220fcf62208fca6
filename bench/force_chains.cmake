# Google Benchmark of the force-chain material-point update (continuum/model/force_chains/).
# Figures: docs/performance.md#force_chains.
add_executable(bench_force_chains ${CMAKE_CURRENT_LIST_DIR}/bench_force_chains.cpp)
target_link_libraries(bench_force_chains PRIVATE granflow_force_chains benchmark::benchmark)
