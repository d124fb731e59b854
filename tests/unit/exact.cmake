# exact_test: the exact-arithmetic layer (rayproof/detail/exact.hpp) checked against
# GMP rationals. GMP's C++ interface is the reference in this test only; the kernel
# never uses it. Included from tests/unit/CMakeLists.txt.
if(NOT TARGET GTest::gtest_main)
  find_package(GTest REQUIRED)
endif()
include(GoogleTest)

find_path(RAYPROOF_GMPXX_INCLUDE_DIR gmpxx.h REQUIRED)
find_library(RAYPROOF_GMPXX_LIBRARY gmpxx REQUIRED)
find_library(RAYPROOF_GMP_LIBRARY gmp REQUIRED)

add_executable(exact_test ${CMAKE_CURRENT_LIST_DIR}/exact_test.cpp)
target_include_directories(exact_test SYSTEM PRIVATE ${RAYPROOF_GMPXX_INCLUDE_DIR})
target_link_libraries(exact_test PRIVATE rayproof::kernel GTest::gtest_main
                      ${RAYPROOF_GMPXX_LIBRARY} ${RAYPROOF_GMP_LIBRARY})
if(DEFINED RAYPROOF_WARNINGS)
  target_compile_options(exact_test PRIVATE ${RAYPROOF_WARNINGS})
endif()
# The random suites are seeded; RAYPROOF_SEED=<decimal> in the environment replays a run.
gtest_discover_tests(exact_test PROPERTIES LABELS unit)
