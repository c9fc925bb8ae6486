# grainlift_fluidity_law: the nonlocal fluidity's cooperativity length and local fluidity
# (fluidity_law.h), written once for the continuum's fluidity equation and the calibration of A.
# The standard library only, so that the continuum engine may link it without TOML or HDF5.
add_library(grainlift_fluidity_law STATIC ${CMAKE_CURRENT_LIST_DIR}/src/rheology/fluidity_law.cc)
target_include_directories(grainlift_fluidity_law PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(grainlift_fluidity_law PRIVATE grainlift_warnings)
