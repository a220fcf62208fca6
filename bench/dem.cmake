# DEM (granflow-dem) timing. Figures and the commands: docs/performance.md#dem.
#   bench_dem_harness: Google Benchmark of one harness sample (accumulate + finalize) per particle.
#   bench_dem_timing:  runs granflow-dem at 1 and 2 ranks on a generated shear deck and reports
#                      particle-steps/s and the harness overhead against an unsampled run.
if(TARGET granflow-dem)
  add_executable(bench_dem_harness ${CMAKE_CURRENT_LIST_DIR}/bench_dem_harness.cpp)
  target_link_libraries(bench_dem_harness PRIVATE granflow_dem_extraction benchmark::benchmark)
  add_executable(bench_dem_timing ${CMAKE_CURRENT_LIST_DIR}/bench_dem_timing.cpp)
  target_link_libraries(bench_dem_timing PRIVATE granflow_dem_deck granflow_core)
  target_compile_definitions(bench_dem_timing PRIVATE
                             GRANFLOW_DEM_DRIVER_PATH="$<TARGET_FILE:granflow-dem>")
  add_dependencies(bench_dem_timing granflow-dem)
endif()
