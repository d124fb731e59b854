// rayproof/detail/fp_model.hpp — refuse to compile under a floating-point model that
// breaks the kernel's guarantees.
//
// Every error bound and every exact decision of the kernel is derived for IEEE 754
// arithmetic as written: each operation correctly rounded, in the order the source gives,
// with infinities, NaNs, signed zeros and subnormals as the standard defines them
// (docs/semantics.md, "Embedding: threads and the floating-point environment"). The
// options below license the compiler to break exactly that: reassociation undoes the
// error-free transformations (two_sum's error term folds to zero), finite-math-only
// deletes the NaN and infinity tests of the validity rules, no-signed-zeros breaks the
// ±0 parallel rays (1/±0 = ±inf), reciprocal math replaces the correctly rounded
// quotients the faithful t is decided from. A certified answer built that way is not
// certified, so the kernel refuses to compile rather than answer wrongly.
//
// What the compilers let a header see:
//   g++      -ffast-math / -Ofast (__FAST_MATH__), -ffinite-math-only
//            (__FINITE_MATH_ONLY__ == 1), -fassociative-math in effect, i.e. with
//            -fno-signed-zeros -fno-trapping-math (__ASSOCIATIVE_MATH__),
//            -freciprocal-math (__RECIPROCAL_MATH__), -fno-signed-zeros
//            (__NO_SIGNED_ZEROS__), -funsafe-math-optimizations (the last three);
//   clang++  -ffast-math / -Ofast / -ffp-model=fast (__FAST_MATH__) and
//            -ffinite-math-only (__FINITE_MATH_ONLY__ == 1); clang 14 defines no macro
//            for -fassociative-math, -freciprocal-math, -fno-signed-zeros,
//            -funsafe-math-optimizations, -fno-honor-nans or -fno-honor-infinities, so
//            those cannot be refused here and must simply not be used (checked: with
//            -fassociative-math -fno-signed-zeros -fno-trapping-math, or
//            -funsafe-math-optimizations, clang 14 folds two_sum's error term to 0, and
//            with -fno-honor-nans it folds every NaN test to false);
//   MSVC     /fp:fast (_M_FP_FAST).
// The unit test fp_model_refused compiles a translation unit under each of these and
// expects this error. Contraction (-ffp-contract=fast, -mfma, -march=native) is not
// refused: the kernel is written to be right under it (detail/eft.hpp).
// RAYPROOF_ALLOW_UNSAFE_FP_MODEL exists only for that test's
// control and for experiments that measure the damage; it voids every promise.
#pragma once

#if !defined(RAYPROOF_ALLOW_UNSAFE_FP_MODEL)
#if defined(__FAST_MATH__)
#error "rayproof: -ffast-math (or -Ofast) breaks the kernel's exact arithmetic and error bounds; build without it"
#endif
#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "rayproof: -ffinite-math-only removes the NaN and infinity tests the kernel's answers rest on; build without it"
#endif
#if defined(__ASSOCIATIVE_MATH__)
#error "rayproof: -fassociative-math reorders the error-free transformations of the certified mode; build without it"
#endif
#if defined(__RECIPROCAL_MATH__)
#error "rayproof: -freciprocal-math changes the correctly rounded quotients the kernel decides from; build without it"
#endif
#if defined(__NO_SIGNED_ZEROS__)
#error "rayproof: -fno-signed-zeros breaks the +-0 direction components the contract defines; build without it"
#endif
#if defined(_M_FP_FAST)
#error "rayproof: /fp:fast breaks the kernel's exact arithmetic and error bounds; use /fp:precise or /fp:strict"
#endif
#endif
