// props_main.cpp — main() of the property suites: GoogleTest, with the RapidCheck case
// count taken from the environment.
//
// RapidCheck reads RC_PARAMS once, on first use. CTest sets RAYPROOF_RC_DEFAULT (see
// CMakeLists.txt) rather than RC_PARAMS, and this main copies it into RC_PARAMS only when
// RC_PARAMS is not already set, so that a user's RC_PARAMS always wins:
//   RC_PARAMS="max_success=1000000" ctest -L property
//   RC_PARAMS="reproduce=..." ./ray_aabb_props --gtest_filter=...
//   RAYPROOF_PROPS_CASE=123 RC_PARAMS="seed=20261121" ./ray_aabb_props --gtest_filter=...
#include <gtest/gtest.h>

#include <cstdlib>

int main(int argc, char** argv) {
    if (const char* def = std::getenv("RAYPROOF_RC_DEFAULT"); def && !std::getenv("RC_PARAMS"))
        setenv("RC_PARAMS", def, 0);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
