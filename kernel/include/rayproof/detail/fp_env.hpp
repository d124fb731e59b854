// rayproof/detail/fp_env.hpp — the run-time floating-point environment the certified and
// conservative modes need, established for each call (a batch: once for the batch) and
// the caller's own restored afterwards.
//
// What is needed. Every error bound of those modes is derived for round-to-nearest-even
// with gradual underflow (subnormals kept, detail/rounding.hpp), and the exact stage
// (detail/exact.hpp) splits and renormalizes with operations that are exact only there.
// A host program may run with another environment: a directed rounding mode (fesetround),
// or flush-to-zero / denormals-are-zero (the FTZ/DAZ bits of MXCSR, which Embree asks its
// users to set on every thread and -ffast-math start-up code sets). Measured without this
// guard: under FTZ/DAZ 40-50% of near-tangent sphere verdicts at 1e-150..1e-300 flip and
// planes at 1e-300 loop for ever in BigDyadic; the directed modes give wrong boxes and
// spheres. Unmasked exceptions (feenableexcept) would turn the kernel's deliberate 1/±0
// into a SIGFPE.
//
// What the guard does. Each guarded entry point reads the control state (x86: one
// _mm_getcsr, an AND and a compare) and takes the common case, the default environment,
// with no other cost: the query is the same inlined code as before. In a foreign
// environment it sets the default control state (keeping the caller's sticky exception
// flags as they were), answers, and writes the caller's word back exactly as it was read
// (so the flags the kernel's own arithmetic raised are dropped in that case; the kernel
// promises nothing about the flags). The scalar queries do this inline
// (in_default_fp_env_inline, below: two asm statements, no call); the batch forms,
// normal() and the surface-point helpers out of line, once per call
// (in_established_fp_env, with an FpEnvGuard).
//
// The state, per architecture:
//   x86 / x86-64 with SSE2 (FLT_EVAL_METHOD == 0 is required anyway): MXCSR. The control
//     bits 6..15 are DAZ, the six exception masks, the rounding control and FTZ; the
//     default is 0x1F80 (all exceptions masked, nearest, neither FTZ nor DAZ), what the
//     x86-64 ABIs start every thread with. The x87 control word (which fesetround also
//     sets) is not touched: the kernel does no x87 arithmetic (no long double).
//   AArch64 with GCC or Clang: FPCR. The control bits are FIZ and AH (bits 0 and 1, the
//     FEAT_AFP flushing and alternate handling), the trap enables (8..12, 15), the
//     rounding mode (22, 23) and FZ (24); the default is all of them 0. FZ16 and DN are
//     left as they are: the kernel does no half-precision arithmetic and never returns a
//     NaN's payload.
//   Anywhere else: <cfenv>'s rounding mode alone (fegetround, fesetround). A flush-to-zero
//     or trap mode of such a target (ARMv7 FPSCR.FZ, PowerPC's NI bit) is NOT covered: a
//     program that sets one there must clear it before querying in those modes.
//
// Why the compiler cannot move the kernel's arithmetic across the switch. GCC and Clang
// without -frounding-math (or -ffp-model=strict) assume the default environment and treat
// arithmetic as free of side effects: they may compute a product before _mm_setcsr or
// fesetround, or after the restore, wherever its operands and uses allow. The kernel does
// not ask its users for those flags (they slow everything down); instead both paths give
// the compiler no freedom. The inline one: the switch and the laundering of the input
// pointers are one asm statement, the pinning of the result's fields (in-out register
// operands) and the restore another (in_default_fp_env_inline). The out-of-line one:
//   - it is a separate function (gnu::noinline), so none of its work can migrate into the
//     caller's code, nor the caller's into it;
//   - after the switch, every input is read through a pointer that comes out of an empty
//     asm statement (fp_env_fence_input: asm volatile with the pointer as an in-out
//     register operand and a "memory" clobber). The compiler cannot know where that pointer
//     points, so every load of an input, and hence every operation on one, comes after the
//     asm; the asm is volatile and clobbers memory, so it stays after the switch (itself a
//     volatile operation with side effects, or a call);
//   - before the restore, the result is made an in-out memory operand of another such asm
//     (fp_env_fence_output), so every operation that feeds it is done before it, and the
//     restore, volatile again, comes after. The batch forms store through `out` and end
//     with a "memory" clobber (fp_env_fence_memory), which no store may cross.
// This is the technique of detail::narrow (an asm the optimizer cannot see through),
// applied to the inputs and outputs. The default path has no asm (nothing to keep apart:
// the environment does not change there); its cost, measured in docs/trade.md, is the
// read and a few ns of register pressure from the inputs' two possible addresses. Constants folded at compile time are folded in round-to-nearest, which is
// what the kernel needs. A compiler without GNU asm (MSVC) gets no fences: it must be
// told (/fp:strict or #pragma fenv_access(on)) not to move arithmetic across
// _mm_setcsr; that configuration is not checked by the suites.
//
// The caller's own arithmetic is its compiler's business: a program that switches the
// environment itself must keep its compiler from moving its own work (and the kernel's
// inlined default path) across that switch, which -frounding-math and strict FP models
// are for; the guard protects the kernel from the environment, not the caller from its
// compiler.
//
// The fast mode is not guarded: it is plain floating point, and its answers in a foreign
// environment are whatever the hardware gives there.
//
// RAYPROOF_NO_FP_ENV_GUARD (defined before the first include) compiles the guard out, so
// that the environment test can show what the guard prevents and the benchmarks can time
// the kernel without it; it voids the certified and conservative promises in a foreign
// environment and must never be defined in one translation unit of a program but not in
// another (an ODR violation).
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/fp_model.hpp>
#include <rayproof/types.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

#if defined(__SSE2__) || defined(_M_X64) || defined(_M_AMD64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#define RAYPROOF_FP_ENV_MXCSR 1
#include <xmmintrin.h>
#elif defined(__aarch64__) && (defined(__GNUC__) || defined(__clang__))
#define RAYPROOF_FP_ENV_FPCR 1
#else
#define RAYPROOF_FP_ENV_CFENV 1
#include <cfenv>
#endif

namespace rayproof::detail {

#if defined(RAYPROOF_FP_ENV_MXCSR)
using FpEnvWord = unsigned int;
inline constexpr FpEnvWord fp_env_control = 0xFFC0u;  // DAZ (6), masks (7-12), rounding (13-14), FTZ (15)
inline constexpr FpEnvWord fp_env_default = 0x1F80u;  // every exception masked, nearest, no FTZ/DAZ
[[nodiscard]] inline FpEnvWord fp_env_read() noexcept { return _mm_getcsr(); }
// With GNU asm, a volatile statement with a "memory" clobber, as the AArch64 form below:
// no load or store moves across it, so fences made of volatile asm statements (the
// scoped queries', detail::in_fp_env_scope) stay on their side of every write.
inline void fp_env_write(FpEnvWord w) noexcept {
#if defined(__GNUC__) || defined(__clang__)
    __asm__ volatile("ldmxcsr %0" : : "m"(w) : "memory");
#else
    _mm_setcsr(w);
#endif
}
#elif defined(RAYPROOF_FP_ENV_FPCR)
using FpEnvWord = std::uint64_t;
inline constexpr FpEnvWord fp_env_control = 0x01C09F03u;  // FIZ, AH, traps (8-12, 15), RMode (22-23), FZ (24)
inline constexpr FpEnvWord fp_env_default = 0;            // no trap, nearest, no flushing
[[nodiscard]] inline FpEnvWord fp_env_read() noexcept {
    FpEnvWord w;
    __asm__ volatile("mrs %0, fpcr" : "=r"(w));
    return w;
}
inline void fp_env_write(FpEnvWord w) noexcept { __asm__ volatile("msr fpcr, %0" : : "r"(w) : "memory"); }
#else
using FpEnvWord = int;                                // fegetround()'s value
inline constexpr FpEnvWord fp_env_control = ~0;       // the whole word is the rounding mode
inline constexpr FpEnvWord fp_env_default = FE_TONEAREST;
[[nodiscard]] inline FpEnvWord fp_env_read() noexcept { return std::fegetround(); }
inline void fp_env_write(FpEnvWord w) noexcept { (void)std::fesetround(w); }
#endif

// True when the control state is the one the kernel needs (always, with the guard
// compiled out). The public entry points test it before each call or batch.
[[nodiscard]] constexpr bool fp_env_is_default_word(FpEnvWord w) noexcept {
#if defined(RAYPROOF_NO_FP_ENV_GUARD)
    static_cast<void>(w);
    return true;
#else
    return (w & fp_env_control) == fp_env_default;
#endif
}
[[nodiscard]] inline bool fp_env_is_default() noexcept {
#if defined(RAYPROOF_NO_FP_ENV_GUARD)
    return true;
#else
    return fp_env_is_default_word(fp_env_read());
#endif
}

// RAII: establishes the default control state for its lifetime when it differs (the
// caller's other bits, and its sticky flags, kept) and writes the caller's word back,
// exactly as read, when it goes out of scope. Not copyable: one scope, one thread. With
// RAYPROOF_NO_FP_ENV_GUARD it switches nothing, as every other guarded path.
class FpEnvGuard {
public:
    FpEnvGuard() noexcept : saved_(fp_env_read()), switched_(!fp_env_is_default_word(saved_)) {
        if (switched_) fp_env_write(static_cast<FpEnvWord>((saved_ & ~fp_env_control) | fp_env_default));
    }
    ~FpEnvGuard() {
        if (switched_) fp_env_write(saved_);
    }
    FpEnvGuard(const FpEnvGuard&) = delete;
    FpEnvGuard& operator=(const FpEnvGuard&) = delete;
    [[nodiscard]] bool switched() const noexcept { return switched_; }

private:
    FpEnvWord saved_;
    bool switched_;
};

// The fences of the header comment. fp_env_fence_input(x) is x, read through a pointer
// the compiler cannot see through, produced after every earlier volatile operation;
// fp_env_fence_output(x) makes x's value, in memory, an input of a volatile operation
// (so it is computed before) and reloads it from there; fp_env_fence_memory() is a
// compiler barrier for every store.
template <class X> [[nodiscard]] inline const X& fp_env_fence_input(const X& x) noexcept {
    const X* p = &x;
#if defined(__GNUC__) || defined(__clang__)
    __asm__ volatile("" : "+r"(p) : : "memory");
#endif
    return *p;
}
template <class X> inline void fp_env_fence_output(X& x) noexcept {
#if defined(__GNUC__) || defined(__clang__)
    __asm__ volatile("" : "+m"(x) : : "memory");
#else
    (void)x;
#endif
}
inline void fp_env_fence_memory() noexcept {
#if defined(__GNUC__) || defined(__clang__)
    __asm__ volatile("" : : : "memory");
#endif
}

// f(in...) in the default environment, the caller's restored after it, with the fences
// above: the path of every guarded entry point outside the default environment. Out of
// line and cold, so that the default path stays the plain inlined query.
template <class F, class... In>
[[gnu::noinline, gnu::cold]] auto in_established_fp_env(F f, const In&... in) noexcept(noexcept(f(in...)))
    -> decltype(f(in...)) {
    const FpEnvGuard guard;
    if constexpr (std::is_void_v<decltype(f(in...))>) {
        f(fp_env_fence_input(in)...);
        fp_env_fence_memory();
    } else {
        auto r = f(fp_env_fence_input(in)...);
        fp_env_fence_output(r);
        return r;
    }
}

// f(in...) in the default environment: called directly when the environment is the
// default (one read and a branch predicted taken), else through in_established_fp_env.
template <class F, class... In>
[[nodiscard]] inline auto in_default_fp_env(F f, const In&... in) noexcept(noexcept(f(in...))) -> decltype(f(in...)) {
    if (!fp_env_is_default()) [[unlikely]]
        return in_established_fp_env(f, in...);
    return f(in...);
}

// The scalar queries' form, inline: a call out of line inside the caller's loop would
// make every value the loop keeps in an XMM register live across a call (all of them are
// caller-saved), and the compiler spills them on the default path too (measured: +10 ns
// per certified plane query). Here the foreign branch is two instructions and no call:
// one asm statement sets the default and launders the input pointers (x86: ldmxcsr; the
// "memory" clobber makes the caller's stores to the inputs happen before it), the query
// runs inline on the laundered pointers, and one asm statement takes the result's fields
// as in-out register operands and restores the caller's word, so the query's arithmetic
// happens between the two and the caller's use of the result after the restore. The
// default branch reads the word, compares and goes on with the same inline query. On a
// target without the two asm forms, the restore is a call after a memory fence.
template <class A, class B> RAYPROOF_ALWAYS_INLINE void fp_env_enter(FpEnvWord w, const A*& a, const B*& b) noexcept {
#if defined(RAYPROOF_FP_ENV_MXCSR) && (defined(__GNUC__) || defined(__clang__))
    __asm__ volatile("ldmxcsr %2" : "+r"(a), "+r"(b) : "m"(w) : "memory");
#elif defined(RAYPROOF_FP_ENV_FPCR)
    __asm__ volatile("msr fpcr, %2" : "+r"(a), "+r"(b) : "r"(w) : "memory");
#else
    fp_env_write(w);
    a = &fp_env_fence_input(*a);
    b = &fp_env_fence_input(*b);
#endif
}
template <class T> RAYPROOF_ALWAYS_INLINE void fp_env_leave(FpEnvWord w, Hit<T>& h) noexcept {
    int v = static_cast<int>(h.verdict);
#if defined(RAYPROOF_FP_ENV_MXCSR) && (defined(__GNUC__) || defined(__clang__))
    __asm__ volatile("ldmxcsr %4" : "+x"(h.t_enter), "+x"(h.t_exit), "+r"(h.face), "+r"(v) : "m"(w));
#elif defined(RAYPROOF_FP_ENV_FPCR)
    __asm__ volatile("msr fpcr, %4" : "+w"(h.t_enter), "+w"(h.t_exit), "+r"(h.face), "+r"(v) : "r"(w));
#else
    fp_env_fence_output(h);
    fp_env_write(w);
#endif
    h.verdict = static_cast<Verdict>(v);
}
RAYPROOF_ALWAYS_INLINE void fp_env_leave(FpEnvWord w, Verdict& verdict) noexcept {
    int v = static_cast<int>(verdict);
#if defined(RAYPROOF_FP_ENV_MXCSR) && (defined(__GNUC__) || defined(__clang__))
    __asm__ volatile("ldmxcsr %1" : "+r"(v) : "m"(w));
#elif defined(RAYPROOF_FP_ENV_FPCR)
    __asm__ volatile("msr fpcr, %1" : "+r"(v) : "r"(w));
#else
    fp_env_fence_output(v);
    fp_env_write(w);
#endif
    verdict = static_cast<Verdict>(v);
}

// f(ray, shape) in the default environment, inline (above): for the scalar queries.
template <class F, class R, class S>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE auto in_default_fp_env_inline(F f, const R& ray, const S& shape) noexcept {
#if defined(RAYPROOF_NO_FP_ENV_GUARD)
    return f(ray, shape);
#else
    const FpEnvWord saved = fp_env_read();
    const bool foreign = (saved & fp_env_control) != fp_env_default;
    const R* r = &ray;
    const S* s = &shape;
    if (foreign) [[unlikely]]
        fp_env_enter(static_cast<FpEnvWord>((saved & ~fp_env_control) | fp_env_default), r, s);
    auto result = f(*r, *s);
    if (foreign) [[unlikely]]
        fp_env_leave(saved, result);
    return result;
#endif
}

// The scalar and packet queries in an FpEnvScope (rayproof/fp_env_scope.hpp): the scope
// has established the default environment, so the query does not read the control
// state. Where the environment may have been switched by the scope's constructor, the
// query's arithmetic must still not be moved before that switch nor after the restore of
// its destructor: the input pointers are laundered by a volatile asm statement (loads
// through them come after it; volatile asm statements keep their order, and the scope's
// switch is one), and the result is made an in-out operand of another (computed before
// it, and so before the scope's restore). Neither has a "memory" clobber: nothing else
// of the caller's needs to stay on one side. Without GNU asm the fences are not
// available and the query takes the per-call guard instead (the same answers).
// RAYPROOF_CHECK_FP_ENV_SCOPE (or a build without NDEBUG) checks the scope's
// precondition at every such query: the control state is the default, else the program
// stops with a message (std::abort), as an assert would.
#if (defined(RAYPROOF_FP_ENV_MXCSR) || defined(RAYPROOF_FP_ENV_FPCR)) && (defined(__GNUC__) || defined(__clang__))
#define RAYPROOF_FP_ENV_SCOPE_FENCED 1
#endif
#if defined(RAYPROOF_CHECK_FP_ENV_SCOPE) || !defined(NDEBUG)
[[noreturn, gnu::cold, gnu::noinline]] inline void fp_env_scope_broken() noexcept {
    std::fputs("rayproof: a query was given an FpEnvScope, but the floating-point environment is not the "
               "default one: it was changed inside the scope, or the scope belongs to another thread\n",
               stderr);
    std::abort();
}
#endif
RAYPROOF_ALWAYS_INLINE void fp_env_scope_check() noexcept {
#if !defined(RAYPROOF_NO_FP_ENV_GUARD) && (defined(RAYPROOF_CHECK_FP_ENV_SCOPE) || !defined(NDEBUG))
    if (!fp_env_is_default()) [[unlikely]]
        fp_env_scope_broken();
#endif
}
#if defined(RAYPROOF_FP_ENV_SCOPE_FENCED)
template <class A, class B> RAYPROOF_ALWAYS_INLINE void fp_env_scope_launder(const A*& a, const B*& b) noexcept {
    __asm__ volatile("" : "+r"(a), "+r"(b));
}
template <class T> RAYPROOF_ALWAYS_INLINE void fp_env_scope_pin(Hit<T>& h) noexcept {
    int v = static_cast<int>(h.verdict);
#if defined(RAYPROOF_FP_ENV_MXCSR)
    __asm__ volatile("" : "+x"(h.t_enter), "+x"(h.t_exit), "+r"(h.face), "+r"(v));
#else
    __asm__ volatile("" : "+w"(h.t_enter), "+w"(h.t_exit), "+r"(h.face), "+r"(v));
#endif
    h.verdict = static_cast<Verdict>(v);
}
RAYPROOF_ALWAYS_INLINE void fp_env_scope_pin(Verdict& verdict) noexcept {
    int v = static_cast<int>(verdict);
    __asm__ volatile("" : "+r"(v));
    verdict = static_cast<Verdict>(v);
}
RAYPROOF_ALWAYS_INLINE void fp_env_scope_pin(std::uint32_t& mask) noexcept { __asm__ volatile("" : "+r"(mask)); }
// Any other result (a packet's PacketHit): through memory.
template <class X> RAYPROOF_ALWAYS_INLINE void fp_env_scope_pin(X& x) noexcept { __asm__ volatile("" : "+m"(x)); }
#endif

// f(ray, shape) in an FpEnvScope: no read of the control state (the fences above).
template <class F, class R, class S>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE auto in_fp_env_scope(F f, const R& ray, const S& shape) noexcept {
#if defined(RAYPROOF_NO_FP_ENV_GUARD)
    return f(ray, shape);
#elif defined(RAYPROOF_FP_ENV_SCOPE_FENCED)
    fp_env_scope_check();
    const R* r = &ray;
    const S* s = &shape;
    fp_env_scope_launder(r, s);
    auto result = f(*r, *s);
    fp_env_scope_pin(result);
    return result;
#else
    return in_default_fp_env(f, ray, shape);
#endif
}

// The modes whose promises need the default environment.
template <class Mode> inline constexpr bool fp_env_guarded = !std::is_same_v<Mode, fast_t>;

}  // namespace rayproof::detail
