# Custom fix styles compiled into granflow-dem (included by dem_coupling/CMakeLists.txt).
#   granflow_dem_fluid  pure parts (lubrication resistances, fluid time-step limits), no LIGGGHTS
#   fix fluid/le        drag + rotational drag + lubrication about the Lees-Edwards flow
#   fix drainage        the box compacting under a normal stress as fast as its liquid drains
add_library(granflow_dem_fluid STATIC ${CMAKE_CURRENT_LIST_DIR}/fluid_time_step.cpp)
target_include_directories(granflow_dem_fluid PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(granflow_dem_fluid PUBLIC granflow_model fmt::fmt)

set(fix_fluid_le_sources
    ${CMAKE_CURRENT_LIST_DIR}/fix_fluid_le.cpp ${CMAKE_CURRENT_LIST_DIR}/fix_fluid_le_arguments.cpp
    ${CMAKE_CURRENT_LIST_DIR}/fix_fluid_le_reach.cpp
    ${CMAKE_CURRENT_LIST_DIR}/fix_fluid_le_lubrication.cpp
    ${CMAKE_CURRENT_LIST_DIR}/fix_drainage.cpp)
target_sources(granflow-dem PRIVATE ${fix_fluid_le_sources})
target_link_libraries(granflow-dem PRIVATE granflow_dem_fluid)
# LIGGGHTS' headers are not -Wextra clean; treat them as system headers.
set_source_files_properties(${fix_fluid_le_sources} PROPERTIES
                            COMPILE_OPTIONS "-isystem;${LIGGGHTS_INCLUDE_DIR}")
