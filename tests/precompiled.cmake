# tests/precompiled.cmake — precompiled third-party headers for the test programs.
#
# GoogleTest, RapidCheck, Eigen and the standard library cost about 4 s of every test
# translation unit's compile (measured with g++ 12 and clang 14: a file that includes
# only them takes 4.2-4.5 s at -O2), and each of the four compiler configurations of
# scripts/test.sh compiles the test programs anew. Under clang (not under g++: see
# rayproof_precompile_test_headers), each group of test programs with the same compile
# options and definitions shares one precompiled header (REUSE_FROM), made by a small
# object library of its own, so that a stage which builds only some of the programs
# never builds a program it did not ask for. Groups of fewer than three programs keep
# none: the header costs about one translation unit to make.
#
# Only third-party and standard headers are precompiled. The kernel's own headers are
# not: some programs define RAYPROOF_* macros (portable limbs, split products, no
# environment guard, counters) that select what the kernel compiles. With
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON every program is built from its own includes
# alone, which is also how the fuzzing build, the consumer tests and the kernel's
# stand-alone header check build theirs.

# _rayproof_targets_under(DIR OUT): every target defined in DIR and its subdirectories.
function(_rayproof_targets_under dir out)
  get_property(found DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub ${subdirs})
    _rayproof_targets_under(${sub} more)
    list(APPEND found ${more})
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

# rayproof_precompile_test_headers(): groups the GoogleTest programs under this directory
# and gives each group of three or more one precompiled header.
function(rayproof_precompile_test_headers)
  # Clang only: with these headers precompiled, g++ 12 at -O2 reports -Warray-bounds
  # errors inside the standard library's std::string code inlined into the tests
  # (ray_aabb_packet_test.cpp, bvh_test.cpp), which it does not report when the same
  # headers are included as text.
  if(CMAKE_DISABLE_PRECOMPILE_HEADERS OR NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    return()
  endif()
  _rayproof_targets_under(${CMAKE_CURRENT_SOURCE_DIR} targets)
  set(keys)
  foreach(t ${targets})
    get_target_property(type ${t} TYPE)
    get_target_property(libs ${t} LINK_LIBRARIES)
    if(NOT type STREQUAL "EXECUTABLE" OR NOT libs)
      continue()
    endif()
    if(NOT ("GTest::gtest" IN_LIST libs OR "GTest::gtest_main" IN_LIST libs))
      continue()
    endif()
    get_target_property(options ${t} COMPILE_OPTIONS)
    get_target_property(definitions ${t} COMPILE_DEFINITIONS)
    get_target_property(pic ${t} POSITION_INDEPENDENT_CODE)
    set(rapidcheck OFF)
    if("rapidcheck" IN_LIST libs)
      set(rapidcheck ON)
    endif()
    # The group's key: what decides whether a precompiled header fits the compile line.
    string(MD5 key "${options}|${definitions}|${pic}|${rapidcheck}")
    if(NOT key IN_LIST keys)
      list(APPEND keys ${key})
      set(group_${key}_options "${options}")
      set(group_${key}_definitions "${definitions}")
      set(group_${key}_pic "${pic}")
      set(group_${key}_rapidcheck ${rapidcheck})
      set(group_${key}_targets)
    endif()
    list(APPEND group_${key}_targets ${t})
  endforeach()

  set(n 0)
  foreach(key ${keys})
    list(LENGTH group_${key}_targets size)
    if(size LESS 3)
      continue()
    endif()
    set(donor rayproof_test_pch_${n})
    math(EXPR n "${n} + 1")
    set(source ${CMAKE_CURRENT_BINARY_DIR}/${donor}.cpp)
    file(CONFIGURE OUTPUT ${source}
         CONTENT "// The translation unit that makes the precompiled header of one group of test programs.\n" @ONLY)
    add_library(${donor} OBJECT ${source})
    target_link_libraries(${donor} PRIVATE GTest::gtest rayproof::kernel)
    target_compile_features(${donor} PRIVATE cxx_std_20)
    set(headers <gtest/gtest.h>)
    if(group_${key}_rapidcheck)
      target_link_libraries(${donor} PRIVATE rapidcheck rapidcheck_gtest)
      list(APPEND headers <rapidcheck.h> <rapidcheck/gtest.h>)
    endif()
    list(APPEND headers <Eigen/Core> <Eigen/Geometry> <algorithm> <array> <cmath> <cstdint> <cstdlib>
         <cstring> <functional> <limits> <memory> <optional> <random> <span> <sstream> <string> <variant>
         <vector>)
    if(group_${key}_options)
      target_compile_options(${donor} PRIVATE ${group_${key}_options})
    endif()
    if(group_${key}_definitions)
      target_compile_definitions(${donor} PRIVATE ${group_${key}_definitions})
    endif()
    if(group_${key}_pic)
      set_target_properties(${donor} PROPERTIES POSITION_INDEPENDENT_CODE ${group_${key}_pic})
    endif()
    target_precompile_headers(${donor} PRIVATE ${headers})
    foreach(t ${group_${key}_targets})
      target_precompile_headers(${t} REUSE_FROM ${donor})
    endforeach()
  endforeach()
endfunction()
