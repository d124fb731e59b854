# exact_test: the exact-arithmetic layer (rayproof/detail/exact.hpp) checked against
# GMP rationals. GMP's C++ interface is a reference in the tests only; the kernel
# never uses it. Included from tests/unit/CMakeLists.txt.
if(NOT TARGET GTest::gtest_main)
  find_package(GTest REQUIRED)
endif()
include(GoogleTest)

find_path(RAYPROOF_GMPXX_INCLUDE_DIR gmpxx.h REQUIRED)
find_library(RAYPROOF_GMPXX_LIBRARY gmpxx REQUIRED)
find_library(RAYPROOF_GMP_LIBRARY gmp REQUIRED)

# compensated_test: the double-word stage (rayproof/detail/compensated.hpp), likewise.
# faithful_test: the contract's t tolerance helper (faithful.hpp) against GMP rationals.
# ray_polyhedron_exact_test: the polyhedron with general planes against GMP rationals.
foreach(t exact_test compensated_test faithful_test ray_polyhedron_exact_test)
  add_executable(${t} ${CMAKE_CURRENT_LIST_DIR}/${t}.cpp)
  target_include_directories(${t} SYSTEM PRIVATE ${RAYPROOF_GMPXX_INCLUDE_DIR})
  target_link_libraries(${t} PRIVATE rayproof::kernel GTest::gtest_main
                        ${RAYPROOF_GMPXX_LIBRARY} ${RAYPROOF_GMP_LIBRARY})
  if(DEFINED RAYPROOF_WARNINGS)
    target_compile_options(${t} PRIVATE ${RAYPROOF_WARNINGS})
  endif()
  # The random suites are seeded; RAYPROOF_SEED=<decimal> in the environment replays a run.
  gtest_discover_tests(${t} PROPERTIES LABELS unit)
endforeach()

# The same exact-arithmetic suite with BigDyadic on the portable two-limb product
# (rayproof/detail/limbs.hpp), as on a compiler without unsigned __int128.
add_executable(exact_test_portable_limbs ${CMAKE_CURRENT_LIST_DIR}/exact_test.cpp)
target_compile_definitions(exact_test_portable_limbs PRIVATE RAYPROOF_PORTABLE_LIMBS=1)
target_include_directories(exact_test_portable_limbs SYSTEM PRIVATE ${RAYPROOF_GMPXX_INCLUDE_DIR})
target_link_libraries(exact_test_portable_limbs PRIVATE rayproof::kernel GTest::gtest_main
                      ${RAYPROOF_GMPXX_LIBRARY} ${RAYPROOF_GMP_LIBRARY})
if(DEFINED RAYPROOF_WARNINGS)
  target_compile_options(exact_test_portable_limbs PRIVATE ${RAYPROOF_WARNINGS})
endif()
gtest_discover_tests(exact_test_portable_limbs TEST_PREFIX portable_limbs. PROPERTIES LABELS unit)

# ray_plane_test checks a certified t against the exact rational N/D: GMP's C++ interface.
target_include_directories(ray_plane_test SYSTEM PRIVATE ${RAYPROOF_GMPXX_INCLUDE_DIR})
target_link_libraries(ray_plane_test PRIVATE ${RAYPROOF_GMPXX_LIBRARY} ${RAYPROOF_GMP_LIBRARY})

# The double-word stage with the split products forced on (RAYPROOF_SPLIT_PRODUCTS,
# rayproof/detail/eft.hpp): Dekker's product on Veltkamp's split, as on a target without
# a fused multiply-add. Built with contraction (scripts/test.sh, contraction stage), it
# checks the split where the compiler can fuse its products.
add_executable(compensated_test_split_products ${CMAKE_CURRENT_LIST_DIR}/compensated_test.cpp)
target_compile_definitions(compensated_test_split_products PRIVATE RAYPROOF_SPLIT_PRODUCTS=1)
target_include_directories(compensated_test_split_products SYSTEM PRIVATE ${RAYPROOF_GMPXX_INCLUDE_DIR})
target_link_libraries(compensated_test_split_products PRIVATE rayproof::kernel GTest::gtest_main
                      ${RAYPROOF_GMPXX_LIBRARY} ${RAYPROOF_GMP_LIBRARY})
if(DEFINED RAYPROOF_WARNINGS)
  target_compile_options(compensated_test_split_products PRIVATE ${RAYPROOF_WARNINGS})
endif()
gtest_discover_tests(compensated_test_split_products TEST_PREFIX split_products. PROPERTIES LABELS unit)
