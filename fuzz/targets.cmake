# fuzz/targets.cmake — the fuzz targets' names (read from fuzz/targets.txt) and their
# plain replay executables (<target>_replay: the harness with replay_main.cpp instead of
# a fuzzing engine, any compiler), shared by fuzz/CMakeLists.txt (the fuzzing build) and
# tests/regressions (the CTest replay of the regressions and the corpora in every build).
#   RAYPROOF_FUZZ_SHAPE_TARGETS   the targets that link the oracle (ray vs shape)
#   RAYPROOF_FUZZ_RENDER_TARGETS  the targets that link the tracer
#   RAYPROOF_FUZZ_SANITIZER_FLAGS the flags of fuzz/sanitizers.txt, as a list
set(RAYPROOF_FUZZ_DIR ${CMAKE_CURRENT_LIST_DIR})
include(${RAYPROOF_FUZZ_DIR}/../tools/cli/cli.cmake)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${RAYPROOF_FUZZ_DIR}/targets.txt ${RAYPROOF_FUZZ_DIR}/sanitizers.txt)

set(RAYPROOF_FUZZ_SHAPE_TARGETS)
set(RAYPROOF_FUZZ_RENDER_TARGETS)
file(STRINGS ${RAYPROOF_FUZZ_DIR}/targets.txt _rayproof_fuzz_lines ENCODING UTF-8 REGEX "^[a-z]")
foreach(_line IN LISTS _rayproof_fuzz_lines)
  string(REGEX MATCH "^([a-z0-9_]+)[ \t]+(oracle|render)[ \t]" _match "${_line}")
  if(NOT _match)
    message(FATAL_ERROR "fuzz/targets.txt: cannot read the line '${_line}'")
  endif()
  if(CMAKE_MATCH_2 STREQUAL "oracle")
    list(APPEND RAYPROOF_FUZZ_SHAPE_TARGETS ${CMAKE_MATCH_1})
  else()
    list(APPEND RAYPROOF_FUZZ_RENDER_TARGETS ${CMAKE_MATCH_1})
  endif()
endforeach()

file(STRINGS ${RAYPROOF_FUZZ_DIR}/sanitizers.txt _rayproof_fuzz_san ENCODING UTF-8 REGEX "^[^#]")
string(JOIN " " _rayproof_fuzz_san ${_rayproof_fuzz_san})
separate_arguments(RAYPROOF_FUZZ_SANITIZER_FLAGS UNIX_COMMAND "${_rayproof_fuzz_san}")

# libFuzzer's FuzzedDataProvider.h lives in clang's resource directory (Debian's
# libclang-common-14-dev, pulled in by the clang package). Adding that whole directory
# to a g++ build breaks it, so the one header is copied into the build tree and that
# directory is put on the replay executables' include path.
if(NOT RAYPROOF_FDP_DIR)
  file(GLOB _rayproof_fdp_candidates
       /usr/lib/llvm-*/lib/clang/*/include/fuzzer/FuzzedDataProvider.h
       /usr/lib/clang/*/include/fuzzer/FuzzedDataProvider.h)
  if(_rayproof_fdp_candidates)
    list(GET _rayproof_fdp_candidates 0 _rayproof_fdp)
    file(COPY ${_rayproof_fdp} DESTINATION ${CMAKE_BINARY_DIR}/fuzz_provider/fuzzer)
    set(RAYPROOF_FDP_DIR ${CMAKE_BINARY_DIR}/fuzz_provider CACHE INTERNAL "")
  else()
    message(WARNING "fuzzer/FuzzedDataProvider.h not found (install clang): the fuzz replay tests are not built")
  endif()
endif()

# What a harness links: the shape targets the kernel and the oracle; the render targets
# (scene_fuzz) the tracer.
function(rayproof_fuzz_link exe harness)
  target_include_directories(${exe} PRIVATE ${RAYPROOF_FUZZ_DIR} ${RAYPROOF_FDP_DIR})
  if(harness IN_LIST RAYPROOF_FUZZ_RENDER_TARGETS)
    target_link_libraries(${exe} PRIVATE rayproof::render rayproof::kernel)
  else()
    target_link_libraries(${exe} PRIVATE rayproof::oracle rayproof::kernel)
    # bvh_fuzz shares its checks with the property suite (generators/scene_check.hpp).
    if(TARGET rayproof_generators)
      target_link_libraries(${exe} PRIVATE rayproof::generators)
    endif()
  endif()
  target_compile_features(${exe} PRIVATE cxx_std_20)
  target_compile_options(${exe} PRIVATE ${RAYPROOF_WARNINGS})
endfunction()

# <harness>_replay, unless an earlier directory already defined it.
function(rayproof_add_fuzz_replay harness)
  if(TARGET ${harness}_replay OR NOT RAYPROOF_FDP_DIR)
    return()
  endif()
  rayproof_add_fuzz_replay_main()
  add_executable(${harness}_replay ${RAYPROOF_FUZZ_DIR}/${harness}.cpp)
  rayproof_fuzz_link(${harness}_replay ${harness})
  target_link_libraries(${harness}_replay PRIVATE rayproof_fuzz_replay_main)
endfunction()

# rayproof_fuzz_replay_main: replay_main.cpp compiled once for every replay executable
# (it reads its command line with CLI11, about 13 s of compile each time). The
# executables take main() from this library; main() calls the harness's
# LLVMFuzzerTestOneInput.
function(rayproof_add_fuzz_replay_main)
  if(TARGET rayproof_fuzz_replay_main)
    return()
  endif()
  add_library(rayproof_fuzz_replay_main STATIC ${RAYPROOF_FUZZ_DIR}/replay_main.cpp)
  target_include_directories(rayproof_fuzz_replay_main PRIVATE ${RAYPROOF_FUZZ_DIR})
  target_link_libraries(rayproof_fuzz_replay_main PUBLIC rayproof_cli)
  target_compile_features(rayproof_fuzz_replay_main PRIVATE cxx_std_20)
  target_compile_options(rayproof_fuzz_replay_main PRIVATE ${RAYPROOF_WARNINGS})
endfunction()

# rayproof_fuzz_seeds: writes the seed corpora, checks the byte format's round trip.
function(rayproof_add_fuzz_seeds)
  if(TARGET rayproof_fuzz_seeds OR NOT TARGET rayproof_generators OR NOT RAYPROOF_FDP_DIR)
    return()
  endif()
  add_executable(rayproof_fuzz_seeds ${RAYPROOF_FUZZ_DIR}/seeds.cpp)
  target_include_directories(rayproof_fuzz_seeds PRIVATE ${RAYPROOF_FUZZ_DIR} ${RAYPROOF_FDP_DIR})
  target_link_libraries(rayproof_fuzz_seeds PRIVATE rayproof::generators rayproof::kernel rayproof_cli)
  target_compile_options(rayproof_fuzz_seeds PRIVATE ${RAYPROOF_WARNINGS})
endfunction()
