# grainlift_statistics: block means, pooled beds, Richardson (statistics.h). The standard
# library only, so that the engines may link it (dem/ does) without seeing TOML, HDF5 or
# deal.II; defined apart from shared/CMakeLists.txt so a GRAINLIFT_ONLY=dem build has it too.
add_library(grainlift_statistics STATIC ${CMAKE_CURRENT_LIST_DIR}/src/statistics/statistics.cc)
target_include_directories(grainlift_statistics PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(grainlift_statistics PRIVATE grainlift_warnings)
