// rayproof/fp_env_scope.hpp — the default floating-point environment established once
// for many queries, instead of checked by each.
//
// Every certified and conservative query answers in the default floating-point
// environment whatever the caller's (detail/fp_env.hpp): it reads the control state at
// each call. The read is not free everywhere: on x86 it is STMXCSR, which some
// processors execute at a throughput of one per ten cycles or so (docs/trade.md, "The
// floating-point environment guard", measures it per query), a sizeable share of a box
// test that otherwise takes fifteen. An embedder's BVH loop, which asks thousands of
// boxes per ray, pays it at every node.
//
// FpEnvScope moves that read out of the loop:
//
//   const rayproof::FpEnvScope env;   // reads the control state once, sets the default if needed
//   for (...) {
//       const std::uint32_t m = verdict(prepared, node.boxes, rayproof::certified, env);
//       ...
//   }                                 // the caller's state written back as it was read
//
// Its constructor reads the calling thread's control state and, only when it differs
// from the default (a directed rounding mode, FTZ, DAZ, an unmasked exception), sets the
// default, keeping the caller's other bits; its destructor writes the caller's word back
// exactly as it was read. The forms of intersect and verdict that take the scope as their
// last argument (a Ray or a PreparedRay against any shape, a PreparedRay against an
// AabbPacket) do not read the control state: they answer what the forms without it answer
// in the default environment, bit for bit in every mode, and the compiler cannot move
// their arithmetic before the scope's switch or after its restore (the fences of
// detail::in_fp_env_scope). The batch forms, the BVH and the surface helpers read the
// state once per call already and take no scope.
//
// Precondition: while the scope lives, the thread that made it does not change the
// environment itself (fesetround, _mm_setcsr, feenableexcept, a library that does), and
// the scope is given only to queries on that thread. It is checked at every scoped query
// in a build without NDEBUG or with RAYPROOF_CHECK_FP_ENV_SCOPE defined: the query reads
// the control state and stops the program with a message (std::abort) when it is not the
// default. Unchecked (NDEBUG alone), a broken precondition voids the certified and
// conservative promises of the scoped queries, as a foreign environment voids them
// without the guard. The scope is not copyable or movable: one block, one thread.
#pragma once

#include <rayproof/detail/fp_env.hpp>

namespace rayproof {

// The scope is detail::FpEnvGuard, the guard the batch forms hold for a call, made by
// the caller for a loop: its writes are volatile asm statements that clobber memory
// (detail::fp_env_write), so the scoped queries' fences stay between them.
class FpEnvScope {
public:
    FpEnvScope() noexcept = default;
    FpEnvScope(const FpEnvScope&) = delete;
    FpEnvScope& operator=(const FpEnvScope&) = delete;
    // Whether the constructor had to set the default (the caller's environment differed).
    [[nodiscard]] bool switched() const noexcept { return guard_.switched(); }

private:
    detail::FpEnvGuard guard_;
};

}  // namespace rayproof
