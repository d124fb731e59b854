// fp_env_test.cpp — the certified and conservative answers do not depend on the
// floating-point environment a host program runs the kernel in.
//
// For each environment (FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO; on x86 also MXCSR FTZ,
// DAZ, FTZ+DAZ, and the invalid, divide-by-zero and overflow exceptions unmasked), every
// shape, float and double: the shared generators' cases (every generator, the invalid one
// included), each also scaled exactly by powers of two to the ends of the exponent range
// (near-tangent spheres at 1e-150..1e-300, boxes near 1e±36 in float, planes at 1e-300,
// subnormal inputs), are answered once in the default environment and once under the
// environment, by the same compiled code, and must agree bit for bit:
//   intersect and verdict, scalar, batch and with a RuntimeMode, in the certified and the
//   conservative mode, with a PreparedRay, and the scalar forms (Ray, PreparedRay,
//   RuntimeMode) given an FpEnvScope made under the environment (fp_env_scope.hpp: they
//   must answer what the forms without it answer in the default environment, and the
//   scope's end must bring the environment tested back); normal, surface_point, spawn_offset, spawn_origin (both sides) and
//   offset_origin for each mode's default-environment hit.
// After every one of those calls the environment must be the one the test set (the
// kernel restores the caller's state). The generators and the comparisons run in the
// default environment; only the kernel calls run under the one tested (answers_under,
// out of line, between two out-of-line switches).
//
// A call that hangs (an exact stage that does not terminate under flush-to-zero) or traps
// stops the program with the case that did it: a watchdog thread and a SIGFPE handler
// print the reproducer and exit with a failure.
//
// Reproduce a case: the failure prints make_case<T, Shape>(generator, seed) and the
// exponents it was scaled by. RAYPROOF_SEED=<decimal> changes the base seed,
// RAYPROOF_FPENV_CASES=<n> the cases per generator (default 150, each also scaled twice).
//
// Built a second time with RAYPROOF_NO_FP_ENV_GUARD (fp_env_test_unguarded, expected to
// fail) to show that the test catches an environment the kernel does not establish.
#include <rayproof/generators.hpp>
#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cfenv>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define FPENV_TEST_MXCSR 1
#endif

namespace {

using namespace rayproof;

// ---- The environments -------------------------------------------------------------

struct Env {
    const char* name;
    int rounding;           // fesetround
    unsigned mxcsr_set;     // MXCSR bits set on top (x86)
    unsigned mxcsr_clear;   // MXCSR bits cleared (x86: exception masks)
};
constexpr unsigned kFtz = 0x8000u, kDaz = 0x0040u, kInvalidMask = 0x0080u, kDivMask = 0x0200u,
                   kOverflowMask = 0x0400u, kMxcsrDefault = 0x1F80u, kMxcsrControl = 0xFFC0u;
const Env kDefault{"default", FE_TONEAREST, 0, 0};

// What a thread's environment is: the rounding mode <cfenv> reports and the control bits
// of MXCSR (DAZ, exception masks, rounding, FTZ).
struct Control {
    int rounding = FE_TONEAREST;
    unsigned mxcsr = kMxcsrDefault;
    bool operator==(const Control&) const = default;
};
Control expected_control(const Env& e) {
    Control c;
    c.rounding = e.rounding;
#if defined(FPENV_TEST_MXCSR)
    const unsigned rc = e.rounding == FE_UPWARD ? 0x4000u : e.rounding == FE_DOWNWARD ? 0x2000u
                      : e.rounding == FE_TOWARDZERO ? 0x6000u : 0u;
    c.mxcsr = ((kMxcsrDefault | rc | e.mxcsr_set) & ~e.mxcsr_clear) & kMxcsrControl;
#endif
    return c;
}
[[gnu::noinline]] Control read_control() {
    Control c;
    c.rounding = std::fegetround();
#if defined(FPENV_TEST_MXCSR)
    c.mxcsr = _mm_getcsr() & kMxcsrControl;
#endif
    return c;
}
std::string describe(const Control& c) {
    std::ostringstream os;
    os << "rounding " << c.rounding << ", MXCSR control 0x" << std::hex << c.mxcsr;
    return os.str();
}
// Out of line, with a memory clobber on each side: no arithmetic of the caller crosses.
[[gnu::noinline]] void enter(const Env& e) {
    __asm__ volatile("" : : : "memory");
    std::fesetround(e.rounding);
#if defined(FPENV_TEST_MXCSR)
    _mm_setcsr(((_mm_getcsr() & ~0x3Fu) | e.mxcsr_set) & ~e.mxcsr_clear);  // sticky flags cleared
#endif
    __asm__ volatile("" : : : "memory");
}
[[gnu::noinline]] void leave() {
    __asm__ volatile("" : : : "memory");
    std::fesetround(FE_TONEAREST);
#if defined(FPENV_TEST_MXCSR)
    _mm_setcsr(kMxcsrDefault);
#endif
    __asm__ volatile("" : : : "memory");
}

// ---- Where the program is, for the watchdog and the SIGFPE handler ------------------

std::atomic<std::uint64_t> progress{0};
char current_case[1024] = "(none)";
const char* current_env = "default";

void note_case(const std::string& s) {
    std::snprintf(current_case, sizeof current_case, "%s", s.c_str());
}
[[noreturn]] void stop(const char* why) {
    std::fprintf(stderr, "\nFAILED: %s under environment %s in\n  %s\n", why, current_env, current_case);
    std::fflush(stderr);
    std::_Exit(3);
}
extern "C" void on_sigfpe(int) { stop("a floating-point trap (SIGFPE)"); }

// Stops the program when no case has finished for `stall` (a kernel call that hangs).
class Watchdog {
public:
    explicit Watchdog(std::chrono::seconds stall) : thread_([this, stall] {
        std::uint64_t seen = progress.load();
        auto last = std::chrono::steady_clock::now();
        while (!done_.load()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            const std::uint64_t now = progress.load();
            if (now != seen) {
                seen = now;
                last = std::chrono::steady_clock::now();
            } else if (std::chrono::steady_clock::now() - last > stall) {
                stop("a kernel call that did not return within the watchdog's limit (a hang)");
            }
        }
    }) {}
    ~Watchdog() {
        done_ = true;
        thread_.join();
    }
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;

private:
    std::atomic<bool> done_{false};
    std::thread thread_;
};

// ---- The answers ------------------------------------------------------------------

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }
template <class T> bool same(const Hit<T>& a, const Hit<T>& b) {
    return a.verdict == b.verdict && a.face == b.face && same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit);
}
template <class T> bool same(const Vec3<T>& a, const Vec3<T>& b) {
    return same_bits(a[0], b[0]) && same_bits(a[1], b[1]) && same_bits(a[2], b[2]);
}
template <class T> bool same(const SurfacePoint<T>& a, const SurfacePoint<T>& b) {
    return same(a.p, b.p) && same(a.error, b.error) && same(a.n, b.n);
}
template <class T> std::string show(const Vec3<T>& v) {
    std::ostringstream os;
    os << std::hexfloat << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
    return os.str();
}

// Everything one mode answers for one case; `hit` is the default environment's
// intersect(), which the surface helpers are given in both runs.
template <class T> struct ModeAnswers {
    Hit<T> scalar, runtime, batch[2];
    Verdict verdict = Verdict::miss, verdict_runtime = Verdict::miss, verdict_batch[2] = {};
    // The forms that take an FpEnvScope, the scope made under the environment tested.
    Hit<T> prepared, scoped, scoped_prepared, scoped_runtime;
    Verdict verdict_prepared = Verdict::miss, verdict_scoped = Verdict::miss, verdict_scoped_prepared = Verdict::miss;
    Vec3<T> normal = Vec3<T>::Zero(), spawn_out = Vec3<T>::Zero(), spawn_in = Vec3<T>::Zero(),
            offset = Vec3<T>::Zero();
    SurfacePoint<T> sp;
    T spawn = 0;
};
template <class T> struct Answers {
    ModeAnswers<T> mode[2];     // certified, conservative
    const char* not_restored = nullptr;  // the first call after which the environment was not the one set
    Control seen;
};

// Compares two answers; the names of the calls that differ, with both values.
template <class T> std::string differences(const ModeAnswers<T>& a, const ModeAnswers<T>& b) {
    std::ostringstream os;
    auto hit = [&](const char* what, const Hit<T>& x, const Hit<T>& y) {
        if (!same(x, y)) os << "\n    " << what << ": default " << x << ", under it " << y;
    };
    auto ver = [&](const char* what, Verdict x, Verdict y) {
        if (x != y) os << "\n    " << what << ": default " << x << ", under it " << y;
    };
    auto vec = [&](const char* what, const Vec3<T>& x, const Vec3<T>& y) {
        if (!same(x, y)) os << "\n    " << what << ": default " << show(x) << ", under it " << show(y);
    };
    hit("intersect", a.scalar, b.scalar);
    // The scoped forms under the environment against the forms without a scope in the
    // default one: the same answers.
    hit("intersect(FpEnvScope)", a.scalar, b.scoped);
    hit("intersect(PreparedRay)", a.prepared, b.prepared);
    hit("intersect(PreparedRay, FpEnvScope)", a.prepared, b.scoped_prepared);
    hit("intersect(RuntimeMode, FpEnvScope)", a.runtime, b.scoped_runtime);
    ver("verdict(FpEnvScope)", a.verdict, b.verdict_scoped);
    ver("verdict(PreparedRay)", a.verdict_prepared, b.verdict_prepared);
    ver("verdict(PreparedRay, FpEnvScope)", a.verdict_prepared, b.verdict_scoped_prepared);
    hit("intersect(RuntimeMode)", a.runtime, b.runtime);
    hit("batch intersect[0]", a.batch[0], b.batch[0]);
    hit("batch intersect[1] (reversed ray)", a.batch[1], b.batch[1]);
    ver("verdict", a.verdict, b.verdict);
    ver("verdict(RuntimeMode)", a.verdict_runtime, b.verdict_runtime);
    ver("batch verdict[0]", a.verdict_batch[0], b.verdict_batch[0]);
    ver("batch verdict[1] (reversed ray)", a.verdict_batch[1], b.verdict_batch[1]);
    vec("normal", a.normal, b.normal);
    vec("surface_point.p", a.sp.p, b.sp.p);
    vec("surface_point.error", a.sp.error, b.sp.error);
    vec("surface_point.n", a.sp.n, b.sp.n);
    if (!same_bits(a.spawn, b.spawn))
        os << "\n    spawn_offset: default " << std::hexfloat << a.spawn << ", under it " << b.spawn << std::defaultfloat;
    vec("spawn_origin(+1)", a.spawn_out, b.spawn_out);
    vec("spawn_origin(-1)", a.spawn_in, b.spawn_in);
    vec("offset_origin", a.offset, b.offset);
    return os.str();
}

// Every call of one mode; after each, the environment must still be `want`.
template <class T, class Shape, class Mode>
void answer_mode(const gen::Case<T, Shape>& c, const Hit<T>& hit, Mode mode, RuntimeMode rm, const Control& want,
                 ModeAnswers<T>& a, Answers<T>& all) {
    auto check = [&](const char* call) {
        if (all.not_restored) return;
        const Control now = read_control();
        if (!(now == want)) {
            all.not_restored = call;
            all.seen = now;
        }
    };
    a.scalar = intersect(c.ray, c.shape, mode);
    check("intersect");
    a.runtime = intersect(c.ray, c.shape, rm);
    check("intersect(RuntimeMode)");
    a.verdict = verdict(c.ray, c.shape, mode);
    check("verdict");
    a.verdict_runtime = verdict(c.ray, c.shape, rm);
    check("verdict(RuntimeMode)");
    const PreparedRay<T> prepared(c.ray);
    a.prepared = intersect(prepared, c.shape, mode);
    check("intersect(PreparedRay)");
    a.verdict_prepared = verdict(prepared, c.shape, mode);
    check("verdict(PreparedRay)");
    {
        const FpEnvScope scope;
        a.scoped = intersect(c.ray, c.shape, mode, scope);
        a.scoped_prepared = intersect(prepared, c.shape, mode, scope);
        a.scoped_runtime = intersect(c.ray, c.shape, rm, scope);
        a.verdict_scoped = verdict(c.ray, c.shape, mode, scope);
        a.verdict_scoped_prepared = verdict(prepared, c.shape, mode, scope);
    }
    check("the end of an FpEnvScope");
    const Ray<T> rays[2] = {c.ray, reversed(c.ray)};
    intersect(std::span<const Ray<T>>(rays), c.shape, mode, std::span<Hit<T>>(a.batch));
    check("batch intersect");
    verdict(std::span<const Ray<T>>(rays), c.shape, mode, std::span<Verdict>(a.verdict_batch));
    check("batch verdict");
    a.normal = normal(c.shape, hit, c.ray);
    check("normal");
    a.sp = surface_point(c.ray, c.shape, hit);
    check("surface_point");
    a.spawn = spawn_offset(a.sp);
    check("spawn_offset");
    a.spawn_out = spawn_origin(a.sp, +1);
    check("spawn_origin(+1)");
    a.spawn_in = spawn_origin(a.sp, -1);
    check("spawn_origin(-1)");
    a.offset = offset_origin(a.sp.p, a.sp.n, T(0.5));
    check("offset_origin");
}

// The answers under `e`: the switch, the calls and the switch back, each out of line.
template <class T, class Shape>
[[gnu::noinline]] Answers<T> answers_under(const Env& e, const gen::Case<T, Shape>& c, const Hit<T> (&hits)[2]) {
    const Control want = expected_control(e);
    Answers<T> a;
    enter(e);
    answer_mode(c, hits[0], certified, RuntimeMode::certified, want, a.mode[0], a);
    answer_mode(c, hits[1], conservative, RuntimeMode::conservative, want, a.mode[1], a);
    leave();
    return a;
}

// The default environment's intersect() of both modes, out of line like the rest.
template <class T, class Shape> [[gnu::noinline]] void default_hits(const gen::Case<T, Shape>& c, Hit<T> (&hits)[2]) {
    hits[0] = intersect(c.ray, c.shape, certified);
    hits[1] = intersect(c.ray, c.shape, conservative);
}

// ---- The cases --------------------------------------------------------------------

std::uint64_t base_seed() {
    const char* s = std::getenv("RAYPROOF_SEED");
    return s ? std::strtoull(s, nullptr, 10) : 20261202u;
}
int cases_per_generator() {
    const char* s = std::getenv("RAYPROOF_FPENV_CASES");
    return s ? std::atoi(s) : 150;
}
std::uint64_t splitmix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// The exponents the cases are scaled by: the ends of the range (subnormal results
// included), where the environments differ most.
template <class T> const std::vector<int>& scale_exponents() {
    static const std::vector<int> d = {-1060, -1000, -900, -800, -700, -500, 500, 900, 1000};
    static const std::vector<int> f = {-145, -135, -125, -120, -110, -60, 60, 110, 120};
    if constexpr (std::is_same_v<T, double>) return d;
    else return f;
}

std::string type_name(std::string_view shape, std::string_view scalar) {
    std::string s(shape);
    s[0] = char(s[0] - 'a' + 'A');
    return "rayproof::" + s + '<' + std::string(scalar) + '>';
}

struct Tally {
    std::uint64_t cases = 0, differ = 0, not_restored = 0;
    std::vector<std::string> shown;
};

// Every case of every generator of (T, Shape), plain and scaled, under `e`.
template <class T, class Shape> Tally run(const Env& e) {
    Tally t;
    const int n = cases_per_generator();
    const auto& ks = scale_exponents<T>();
    for (const auto& g : gen::generators<T, Shape>()) {
        const std::uint64_t stream = base_seed() ^ gen::name_hash(std::string(gen::shape_name<Shape>()) + "/" +
                                                                  std::string(gen::scalar_name<T>()) + "/" +
                                                                  std::string(g.name));
        for (int i = 0; i < n; ++i) {
            const std::uint64_t seed = splitmix(stream + std::uint64_t(i));
            const auto base = gen::make_case<T, Shape>(g.name, seed);
            // The case itself, then scaled twice: positions and direction by 2^k (t
            // unchanged), then also the axes / normal by 2^(k/2); a k that is not exact
            // is halved until it is.
            for (int variant = 0; variant < 3; ++variant) {
                auto c = base;
                int k = 0, ka = 0;
                if (variant > 0) {
                    k = ks[std::size_t(splitmix(seed + std::uint64_t(variant)) % ks.size())];
                    ka = variant == 2 ? k / 2 : 0;
                    while (k != 0 && !gen::exact_scale(c, k, k, ka)) {
                        k /= 2;
                        ka /= 2;
                    }
                    if (k == 0 && variant > 0) continue;
                }
                std::ostringstream where;
                where << "rayproof::gen::make_case<" << gen::scalar_name<T>() << ", "
                      << type_name(gen::shape_name<Shape>(), gen::scalar_name<T>()) << ">(\"" << g.name << "\", 0x" << std::hex << seed << std::dec << ")";
                if (variant > 0) where << " scaled by exact_scale(c, " << k << ", " << k << ", " << ka << ")";
                where << "\n  " << c;
                note_case(where.str());

                Hit<T> hits[2];
                default_hits(c, hits);
                const Answers<T> ref = answers_under(kDefault, c, hits);
                const Answers<T> got = answers_under(e, c, hits);
                ++t.cases;
                ++progress;
                EXPECT_EQ(ref.not_restored, nullptr) << "the default environment changed after "
                                                     << ref.not_restored << ": " << describe(ref.seen);
                std::string diff;
                for (int m = 0; m < 2; ++m) {
                    const std::string d = differences(ref.mode[m], got.mode[m]);
                    if (!d.empty()) diff += std::string("\n  ") + (m == 0 ? "certified" : "conservative") + ":" + d;
                }
                if (!diff.empty()) {
                    ++t.differ;
                    if (t.shown.size() < 3) t.shown.push_back(where.str() + diff);
                }
                if (got.not_restored) {
                    ++t.not_restored;
                    if (t.shown.size() < 3)
                        t.shown.push_back(where.str() + "\n  the environment after " + got.not_restored + " was " +
                                          describe(got.seen) + ", set " + describe(expected_control(e)));
                }
            }
        }
    }
    return t;
}

// One shape and scalar type under `e`: its line of the table, and its failures.
template <class T, class Shape> void check_one(const Env& e, std::ostream& table) {
    const Tally t = run<T, Shape>(e);
    const std::string name = type_name(gen::shape_name<Shape>(), gen::scalar_name<T>());
    table << "  " << name << ": " << t.cases << " cases, " << t.differ << " answered differently, " << t.not_restored
          << " left the environment changed\n";
    EXPECT_EQ(t.differ, 0u) << name << " under " << e.name << ": " << t.differ << " of " << t.cases
                            << " cases answered differently";
    EXPECT_EQ(t.not_restored, 0u) << name << " under " << e.name << ": the environment was not restored in "
                                  << t.not_restored << " cases";
    for (const auto& s : t.shown) ADD_FAILURE() << "under " << e.name << ": " << s;
}

// One environment: every shape, float and double.
void check_environment(const Env& e) {
    // One case is some twenty kernel calls: well under a millisecond, even scaled to the
    // exponent range's ends. Five seconds without a finished case is a hang, not a slow
    // machine; the unguarded build waits out this limit in each environment that hangs.
    const Watchdog watchdog(std::chrono::seconds(5));
    current_env = e.name;
    std::ostringstream table;
    table << "environment " << e.name << " (base seed " << base_seed() << ", " << cases_per_generator()
          << " cases per generator, each also scaled twice):\n";
    check_one<float, Aabb<float>>(e, table);
    check_one<double, Aabb<double>>(e, table);
    check_one<float, Obb<float>>(e, table);
    check_one<double, Obb<double>>(e, table);
    check_one<float, Plane<float>>(e, table);
    check_one<double, Plane<double>>(e, table);
    check_one<float, Sphere<float>>(e, table);
    check_one<double, Sphere<double>>(e, table);
    std::cout << table.str();
    current_env = "default";
}

class FpEnvironment : public ::testing::Test {
protected:
    void SetUp() override { std::signal(SIGFPE, on_sigfpe); }
    void TearDown() override { std::signal(SIGFPE, SIG_DFL); }
};

TEST_F(FpEnvironment, Upward) { check_environment({"FE_UPWARD", FE_UPWARD, 0, 0}); }
TEST_F(FpEnvironment, Downward) { check_environment({"FE_DOWNWARD", FE_DOWNWARD, 0, 0}); }
TEST_F(FpEnvironment, TowardZero) { check_environment({"FE_TOWARDZERO", FE_TOWARDZERO, 0, 0}); }
#if defined(FPENV_TEST_MXCSR)
TEST_F(FpEnvironment, FlushToZero) { check_environment({"FTZ", FE_TONEAREST, kFtz, 0}); }
TEST_F(FpEnvironment, DenormalsAreZero) { check_environment({"DAZ", FE_TONEAREST, kDaz, 0}); }
TEST_F(FpEnvironment, FlushToZeroAndDenormalsAreZero) { check_environment({"FTZ+DAZ", FE_TONEAREST, kFtz | kDaz, 0}); }
TEST_F(FpEnvironment, ExceptionsUnmasked) {
    check_environment({"invalid, divide-by-zero and overflow unmasked", FE_TONEAREST, 0,
                       kInvalidMask | kDivMask | kOverflowMask});
}
TEST_F(FpEnvironment, DirectedRoundingWithFlushToZero) {
    check_environment({"FE_UPWARD with FTZ+DAZ", FE_UPWARD, kFtz | kDaz, 0});
}
#endif

}  // namespace
