# grainlift_machine: what memory the process may still take (machine/memory.h). The standard
# library and Linux's /proc only, so that the engines may link it without seeing TOML, HDF5 or
# deal.II; defined apart from shared/CMakeLists.txt so a GRAINLIFT_ONLY=dem build has it too.
add_library(grainlift_machine STATIC ${CMAKE_CURRENT_LIST_DIR}/src/machine/memory.cc)
target_include_directories(grainlift_machine PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(grainlift_machine PRIVATE grainlift_warnings)
