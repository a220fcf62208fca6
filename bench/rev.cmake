add_executable(bench_rev ${CMAKE_CURRENT_LIST_DIR}/bench_rev.cpp)
target_link_libraries(bench_rev PRIVATE granflow_rev benchmark::benchmark)
