# rayproof_cli: the one way the programs read and report their command lines (CLI11,
# tools/cli/rayproof/cli.hpp). Included by every directory that builds a program.
include_guard(GLOBAL)
find_package(CLI11 2 CONFIG REQUIRED GLOBAL)
add_library(rayproof_cli INTERFACE)
target_include_directories(rayproof_cli INTERFACE ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(rayproof_cli INTERFACE CLI11::CLI11)
