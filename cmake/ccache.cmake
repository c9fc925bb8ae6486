# ccache for every compile of the including project (the main one, tests/fuzz/project,
# tests/other_cpus/project), with the paths below the repository hashed relative to it
# (CCACHE_BASEDIR) and the compiling folder left out of debug builds' hashes (CCACHE_NOHASHDIR):
# a second clone of the repository (a fresh checkout, CI's clean clone) reuses the objects of
# the first.
find_program(CCACHE_PROGRAM ccache)
if(CCACHE_PROGRAM)
  get_filename_component(grainlift_ccache_root ${CMAKE_CURRENT_LIST_DIR}/.. ABSOLUTE)
  set(grainlift_ccache env CCACHE_BASEDIR=${grainlift_ccache_root} CCACHE_NOHASHDIR=1
      ${CCACHE_PROGRAM})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${grainlift_ccache})
  set(CMAKE_C_COMPILER_LAUNCHER ${grainlift_ccache})
endif()
