# rayproof_cli: the one way the programs read and report their command lines (CLI11,
# tools/cli/rayproof/cli.hpp). Included by every directory that builds a program.
include_guard(GLOBAL)
if(NOT TARGET CLI11::CLI11)
  find_package(CLI11 2 CONFIG REQUIRED GLOBAL)
endif()
add_library(rayproof_cli INTERFACE)
target_include_directories(rayproof_cli INTERFACE ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(rayproof_cli INTERFACE CLI11::CLI11)

# rayproof_cli_tests(TARGET [NAME name] [BEFORE args...] OPTIONS words... [MALFORMED option value]):
# CTest tests (label cli) of a program's command line, run with BEFORE first (a
# subcommand, required arguments):
#   cli.<name>.help       --help exits 0 and names every word of OPTIONS
#   cli.<name>.unknown    an unknown option exits 2 naming it, with the usage on stderr
#   cli.<name>.malformed  `option value` exits 2 naming the option, with the usage
function(rayproof_cli_tests target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "NAME" "BEFORE;OPTIONS;MALFORMED")
  if(NOT arg_NAME)
    set(arg_NAME ${target})
  endif()
  set(run ${CMAKE_COMMAND} -DPROGRAM=$<TARGET_FILE:${target}>)
  set(check ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/check.cmake)
  list(JOIN arg_BEFORE "," before)
  list(JOIN arg_OPTIONS "," words)
  add_test(NAME cli.${arg_NAME}.help
    COMMAND ${run} "-DARGS=${before},--help" -DSTATUS=0 "-DWORDS=${words}" -P ${check})
  add_test(NAME cli.${arg_NAME}.unknown
    COMMAND ${run} "-DARGS=${before},--no-such-option" -DSTATUS=2 -DWORDS=--no-such-option -P ${check})
  set(tests cli.${arg_NAME}.help cli.${arg_NAME}.unknown)
  if(arg_MALFORMED)
    list(GET arg_MALFORMED 0 option)
    list(JOIN arg_MALFORMED "," malformed)
    add_test(NAME cli.${arg_NAME}.malformed
      COMMAND ${run} "-DARGS=${before},${malformed}" -DSTATUS=2 -DWORDS=${option} -P ${check})
    list(APPEND tests cli.${arg_NAME}.malformed)
  endif()
  set_tests_properties(${tests} PROPERTIES LABELS cli TIMEOUT 60)
endfunction()
