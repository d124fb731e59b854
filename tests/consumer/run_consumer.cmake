# Run by CTest in script mode: one way into the kernel, as README.md's "Use it in your
# project" shows it, from a clean work directory.
#   WAY           find_package | no_exceptions | add_subdirectory | fetchcontent | pkg_config
#   RAYPROOF_DIR  the rayproof source tree
#   CONSUMER_DIR  this directory (consumer.cpp and the consumer projects)
#   WORK_DIR      scratch directory, removed first
#   CXX, GENERATOR, PKG_CONFIG
# find_package, no_exceptions (the same with -fno-exceptions) and pkg_config first run
# the one-command kernel-only install. Every way then builds consumer.cpp with the
# kernel's include directory as plain -I and strict warnings, runs it and checks its
# verdict line (add_subdirectory, fetchcontent and pkg_config its plumbing set:
# consumer.cpp says why).
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(step)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    list(JOIN ARGV " " command)
    message(FATAL_ERROR "consumer step failed (${rc}): ${command}\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

include(${RAYPROOF_DIR}/kernel/cmake/rayproofVersion.cmake)
rayproof_read_version(version ${RAYPROOF_DIR}/kernel/include/rayproof/version.hpp)

# --- the kernel-only install: the source tree configured with RAYPROOF_KERNEL_ONLY=ON --
set(prefix ${WORK_DIR}/prefix)
if(WAY MATCHES "^(find_package|no_exceptions|pkg_config)$")
  step(${CMAKE_COMMAND} -S ${RAYPROOF_DIR} -B ${WORK_DIR}/kernel -G ${GENERATOR}
       -DCMAKE_CXX_COMPILER=${CXX} -DRAYPROOF_KERNEL_ONLY=ON)
  step(${CMAKE_COMMAND} --install ${WORK_DIR}/kernel --prefix ${prefix})
  # Only Eigen was searched for.
  file(STRINGS ${WORK_DIR}/kernel/CMakeCache.txt searched REGEX "^[A-Za-z0-9_]+_DIR:PATH=")
  list(FILTER searched EXCLUDE REGEX "^Eigen3_DIR:")
  if(searched)
    message(FATAL_ERROR "the kernel-only configure searched for more than Eigen: ${searched}")
  endif()
  foreach(f include/rayproof/rayproof.hpp include/rayproof/version.hpp share/cmake/rayproof/rayproofConfig.cmake
            share/cmake/rayproof/rayproofConfigVersion.cmake share/pkgconfig/rayproof.pc share/doc/rayproof/LICENSE)
    if(NOT EXISTS ${prefix}/${f})
      message(FATAL_ERROR "the kernel-only install did not place ${f}")
    endif()
  endforeach()
  # The version file takes the header's version and does not depend on the architecture:
  # asked for by a consumer of another pointer size, it still accepts.
  set(PACKAGE_FIND_NAME rayproof)
  set(PACKAGE_FIND_VERSION ${version})
  string(REPLACE "." ";" parts ${version})
  list(GET parts 0 PACKAGE_FIND_VERSION_MAJOR)
  list(GET parts 1 PACKAGE_FIND_VERSION_MINOR)
  list(GET parts 2 PACKAGE_FIND_VERSION_PATCH)
  set(PACKAGE_FIND_VERSION_COUNT 3)
  set(CMAKE_SIZEOF_VOID_P 4)
  include(${prefix}/share/cmake/rayproof/rayproofConfigVersion.cmake)
  if(NOT PACKAGE_VERSION STREQUAL version OR NOT PACKAGE_VERSION_EXACT OR PACKAGE_VERSION_UNSUITABLE)
    message(FATAL_ERROR "rayproofConfigVersion.cmake: version '${PACKAGE_VERSION}' (header: ${version}), "
                        "exact '${PACKAGE_VERSION_EXACT}', unsuitable for a 32-bit consumer '${PACKAGE_VERSION_UNSUITABLE}'")
  endif()
endif()

# --- build the consumer ----------------------------------------------------------------
set(build ${WORK_DIR}/build)
set(cmake_args -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
if(WAY STREQUAL "find_package" OR WAY STREQUAL "no_exceptions")
  set(no_exceptions OFF)
  if(WAY STREQUAL "no_exceptions")
    set(no_exceptions ON)
  endif()
  step(${CMAKE_COMMAND} -S ${CONSUMER_DIR}/find_package -B ${build} ${cmake_args}
       -DCMAKE_PREFIX_PATH=${prefix} -DRAYPROOF_EXPECTED_VERSION=${version} -DCONSUMER_NO_EXCEPTIONS=${no_exceptions})
  set(include_dir ${prefix}/include)
elseif(WAY STREQUAL "add_subdirectory" OR WAY STREQUAL "fetchcontent")
  set(project subdirectory)
  if(WAY STREQUAL "fetchcontent")
    set(project fetchcontent)
  endif()
  # No CMAKE_BUILD_TYPE: the parent's cache must still have none afterwards.
  step(${CMAKE_COMMAND} -S ${CONSUMER_DIR}/${project} -B ${build} ${cmake_args} -DRAYPROOF_DIR=${RAYPROOF_DIR})
  set(include_dir ${RAYPROOF_DIR}/kernel/include)
elseif(WAY STREQUAL "pkg_config")
  if(NOT PKG_CONFIG)
    message(FATAL_ERROR "pkg-config was not found (scripts/common.sh installs it)")
  endif()
  set(ENV{PKG_CONFIG_PATH} ${prefix}/share/pkgconfig)
  step(${PKG_CONFIG} --modversion rayproof)
  string(STRIP "${step_output}" modversion)
  if(NOT modversion STREQUAL version)
    message(FATAL_ERROR "pkg-config --modversion rayproof gives '${modversion}', the header ${version}")
  endif()
  step(${PKG_CONFIG} --libs rayproof)
  string(STRIP "${step_output}" libs)
  if(NOT libs STREQUAL "")
    message(FATAL_ERROR "pkg-config --libs rayproof gives '${libs}' for a header-only kernel")
  endif()
  step(${PKG_CONFIG} --print-requires rayproof)
  if(NOT step_output MATCHES "^eigen3 >= 3.4")
    message(FATAL_ERROR "rayproof.pc requires '${step_output}', not eigen3 >= 3.4")
  endif()
  # README.md's command line, with the test's warnings: Eigen's directory as -isystem
  # (Eigen's own headers are not -Wconversion clean), the kernel's as plain -I.
  file(MAKE_DIRECTORY ${build})
  set(flags "-O0 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror")
  set(line "'${CXX}' -std=c++20 ${flags} -DCONSUMER_PLUMBING -DCONSUMER_EXPECTED_VERSION='\"${version}\"' \
$(pkg-config --cflags-only-I eigen3 | sed 's/-I/-isystem /g') $(pkg-config --cflags rayproof) \
'${CONSUMER_DIR}/consumer.cpp' -o '${build}/consumer'")
  message(STATUS "${line}")
  step(sh -c "${line}")
  # Its -I for the kernel: the installed include directory.
  step(${PKG_CONFIG} --cflags rayproof)
  separate_arguments(cflags UNIX_COMMAND "${step_output}")
  file(REAL_PATH ${prefix}/include include_dir)
  set(found OFF)
  foreach(flag IN LISTS cflags)
    if(flag MATCHES "^-I(.+)$")
      file(REAL_PATH ${CMAKE_MATCH_1} dir)
      if(dir STREQUAL include_dir)
        set(found ON)
      endif()
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "pkg-config --cflags rayproof gives no -I for ${include_dir}: ${step_output}")
  endif()
else()
  message(FATAL_ERROR "unknown WAY '${WAY}'")
endif()

if(NOT WAY STREQUAL "pkg_config")
  step(${CMAKE_COMMAND} --build ${build})
  # The compile line of consumer.cpp, as the build ran it.
  file(READ ${build}/compile_commands.json commands)
  string(JSON n LENGTH "${commands}")
  math(EXPR last "${n} - 1")
  set(command_line "")
  foreach(i RANGE ${last})
    string(JSON file GET "${commands}" ${i} file)
    if(file MATCHES "consumer\\.cpp$")
      string(JSON command_line GET "${commands}" ${i} command)
    endif()
  endforeach()

  # The kernel's headers were seen with plain -I, not -isystem (which hides their warnings).
  string(FIND " ${command_line} " " -isystem ${include_dir} " as_system)
  string(FIND " ${command_line} " " -I${include_dir} " as_plain)
  if(as_system GREATER_EQUAL 0 OR as_plain LESS 0)
    message(FATAL_ERROR "the kernel's include directory ${include_dir} is not passed with plain -I: ${command_line}")
  endif()
endif()

step(${build}/consumer)
message(STATUS "${step_output}")
if(NOT step_output MATCHES "rayproof consumer: all [0-9]+ checks passed")
  message(FATAL_ERROR "unexpected consumer output: ${step_output}")
endif()
