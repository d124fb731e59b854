// rayproof/version.hpp — the kernel's version, the one place it is written.
//
// The build reads the three numbers below (CMake's project() version, the package
// version file and rayproof.pc all come from them), so a release changes this file
// alone. For code that must adapt to the version:
//
//   #if RAYPROOF_VERSION >= 100  // 0.1.0 or later
//
// RAYPROOF_VERSION is MAJOR * 10000 + MINOR * 100 + PATCH (MINOR and PATCH stay below
// 100), so later versions compare greater. RAYPROOF_VERSION_STRING is "MAJOR.MINOR.PATCH",
// a string literal. Only macros: this header compiles as C++ of any standard and as C.
#pragma once

#define RAYPROOF_VERSION_MAJOR 0
#define RAYPROOF_VERSION_MINOR 1
#define RAYPROOF_VERSION_PATCH 0

#define RAYPROOF_VERSION \
    (RAYPROOF_VERSION_MAJOR * 10000 + RAYPROOF_VERSION_MINOR * 100 + RAYPROOF_VERSION_PATCH)

#define RAYPROOF_VERSION_DETAIL_STR(x) #x
#define RAYPROOF_VERSION_DETAIL_XSTR(x) RAYPROOF_VERSION_DETAIL_STR(x)
#define RAYPROOF_VERSION_STRING                          \
    RAYPROOF_VERSION_DETAIL_XSTR(RAYPROOF_VERSION_MAJOR) \
    "." RAYPROOF_VERSION_DETAIL_XSTR(RAYPROOF_VERSION_MINOR) "." RAYPROOF_VERSION_DETAIL_XSTR(RAYPROOF_VERSION_PATCH)

#if RAYPROOF_VERSION_MINOR > 99 || RAYPROOF_VERSION_PATCH > 99
#error "rayproof/version.hpp: MINOR and PATCH must stay below 100 for RAYPROOF_VERSION to order versions"
#endif
