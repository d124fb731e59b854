// bvh_props.cpp — RapidCheck properties of the BVH (bvh.hpp) and of the brute-force
// closest hit it must equal (closest.hpp), float and double, W = 4 and 8, every mode.
//
// Cases: the scene generators (rayproof/generators/scene_gen.hpp: ties in t_enter,
// duplicated, coincident and touching primitives, rays along shared faces and edges,
// ranges cut at a face, origins inside primitives, every magnitude, 0 to ~3000
// primitives, invalid primitives), stratified and seeded as the shape suites' cases
// (strata.hpp): case i of a run is scene generator i mod G's scene from a seed hashed
// from (suite seed, "scene", type, i). The BVH of a case is built with a leaf size and a
// bin count drawn from the case (shrunk towards 1 and 2 by RapidCheck on a failure).
// What each property holds is written in rayproof/generators/scene_check.hpp, shared
// with the fuzz target bvh_fuzz:
//   BruteForceMatchesOracle   the reference itself against the exact oracle: the
//                             certified closest index has the smallest exact t_enter
//                             (ties to the lowest index), its Hit exact; any_hit the
//                             lowest index hit; conservative never misses and encloses
//   BvhEqualsBruteForceW4/W8  certified closest_hit bit for bit (index and Hit);
//                             any_hit's verdict and index; conservative never misses what
//                             certified brute force hits and encloses the exact interval;
//                             fast verdict validity; for_each_candidate visits every
//                             primitive hit on [t_min, t_limit] (t_max, a drawn limit,
//                             and a limit lowered by the callback)
//   CertifiedScalingKeepsIndex oracle-free: the whole scene scaled by an exact power of
//                             two (t unchanged) gives the same certified index, each t the
//                             same or the adjacent float
//   GeneratorsDeliver         the generators make what their names say (ties in exact
//                             t_enter, invalid primitives, scene sizes)
// The run's case count is RC_PARAMS max_success (the CTest default for this suite is in
// tests/props/CMakeLists.txt: scenes are ~50 times the work of a single shape). A failure
// prints the suite seed, the case, the generator, the command that reruns that case
// alone, the call that rebuilds the scene, the scene in hexfloat, and RapidCheck's
// RC_PARAMS="reproduce=..." string.
#include "props_support.hpp"

#include <rayproof/bvh.hpp>
#include <rayproof/generators/scene_check.hpp>
#include <rayproof/generators/scene_gen.hpp>

namespace {

using namespace rayproof;
using namespace rayproof::props;
using Failure = std::optional<std::string>;

inline constexpr std::uint64_t kOptionsSalt = 21, kLimitSalt = 22;

template <class T> struct ScenePlan {
    std::uint64_t suite_seed = 0;
    std::uint64_t cases = 0;
    std::optional<std::uint64_t> only;

    static std::size_t generator_count() { return gen::scene_generators<T>().size(); }
    std::size_t generator_of(std::uint64_t i) const { return std::size_t(i % generator_count()); }
    std::uint64_t case_seed(std::uint64_t i) const {
        const std::uint64_t key = splitmix(splitmix(splitmix(suite_seed) ^ gen::name_hash("scene")) ^
                                           gen::name_hash(gen::scalar_name<T>()));
        return splitmix(key + i);
    }
    std::uint64_t choice(std::uint64_t i, std::uint64_t salt) const { return splitmix(case_seed(i) ^ splitmix(salt)); }
    gen::Scene<T> make(std::uint64_t i) const {
        gen::Rng rng(case_seed(i));
        return gen::scene_generators<T>()[generator_of(i)].make(rng);
    }
    std::uint64_t first() const { return only ? *only : 0; }
    std::uint64_t end() const { return only ? *only + 1 : cases; }
};

template <class T> struct DrawnScene {
    const ScenePlan<T>* plan;
    std::uint64_t index;
    gen::Scene<T> s;

    std::uint64_t seed() const { return plan->case_seed(index); }
    std::uint64_t choice(std::uint64_t salt) const { return plan->choice(index, salt); }
    std::string where() const {
        std::ostringstream os;
        os << "case " << index << " of suite seed " << plan->suite_seed << ", scene generator '" << s.generator
           << "', case seed 0x" << std::hex << seed() << std::dec << "\n  this case alone: RAYPROOF_PROPS_CASE=" << index
           << " RC_PARAMS=\"seed=" << plan->suite_seed << "\" ./bvh_props --gtest_filter='" << current_test()
           << "'\n  its scene: rayproof::gen::make_scene<" << gen::scalar_name<T>() << ">(\"" << s.generator << "\", 0x"
           << std::hex << seed() << std::dec << ")\n  " << s;
        return os.str();
    }
};

// As run_cases (props_support.hpp), over the scene generators.
template <class T, class Body> void run_scenes(Body body) {
    namespace rcd = ::rc::detail;
    const rcd::Configuration& config = rcd::configuration();
    std::string error;
    ScenePlan<T> plan{config.testParams.seed, std::uint64_t(config.testParams.maxSuccess), case_from_environment(error)};
    ASSERT_TRUE(error.empty()) << error;
    const std::string prefix = current_test() + "#seed=";
    const auto under_rapidcheck = [&](std::uint64_t i) {
        rcd::TestMetadata meta;
        meta.id = prefix + std::to_string(plan.suite_seed) + ",case=" + std::to_string(i);
        meta.description = meta.id;
        rcd::TestParams params = config.testParams;
        params.maxSuccess = 1;
        const auto result = rcd::checkTestable(
            [&] {
                const DrawnScene<T> d{&plan, i, plan.make(i)};
                if (const Failure failure = body(d, RapidPick{})) RC_FAIL(*failure + "\n  " + d.where());
            },
            meta, params);
        std::ostringstream os;
        rcd::printResultMessage(result, os);
        if (result.template is<rcd::SuccessResult>())
            ADD_FAILURE() << "case " << i << " failed, then passed when run again under RapidCheck\n  "
                          << DrawnScene<T>{&plan, i, plan.make(i)}.where();
        else
            ADD_FAILURE() << os.str();
    };
    if (!config.reproduce.empty()) {
        for (const auto& entry : config.reproduce) {
            const std::string& id = entry.first;
            const auto comma = id.find(",case=");
            if (id.compare(0, prefix.size(), prefix) == 0 && comma != std::string::npos) {
                plan.suite_seed = std::stoull(id.substr(prefix.size(), comma - prefix.size()));
                under_rapidcheck(std::stoull(id.substr(comma + 6)));
                return;
            }
        }
        GTEST_SKIP() << "RC_PARAMS reproduce= names other properties";
    }
    std::vector<std::uint64_t> count(plan.generator_count(), 0);
    for (std::uint64_t i = plan.first(); i < plan.end(); ++i) {
        ++count[plan.generator_of(i)];
        const DrawnScene<T> d{&plan, i, plan.make(i)};
        if (body(d, PlainPick{})) {
            under_rapidcheck(i);
            break;
        }
    }
    std::cout << "cases per scene generator (" << gen::scalar_name<T>() << "):";
    for (std::size_t g = 0; g < count.size(); ++g) std::cout << ' ' << gen::scene_generators<T>()[g].name << ' ' << count[g];
    std::cout << '\n';
}

template <class T> class BvhProps : public ::testing::Test {};
TYPED_TEST_SUITE(BvhProps, Scalars, ScalarNames);

TYPED_TEST(BvhProps, BruteForceMatchesOracle) {
    using T = TypeParam;
    run_scenes<T>([](const DrawnScene<T>& d, auto) -> Failure {
        return gen::check_brute_force(d.s.ray, d.s.view(), gen::exact_answers(d.s.ray, d.s.view()));
    });
}

// The BVH options of a case: leaf size 1..8 and bins 2..32 from the case seed, shrunk
// towards 1 and 2.
template <class Pick> BvhOptions options_of(std::uint64_t choice, Pick pick) {
    BvhOptions o;
    o.leaf_size = pick(1 + int(choice % 8), 1);
    o.bins = pick(2 + int((choice >> 8) % 31), 2);
    return o;
}

template <class T, int W> void bvh_equals_brute_force() {
    run_scenes<T>([](const DrawnScene<T>& d, auto pick) -> Failure {
        const BvhOptions o = options_of(d.choice(kOptionsSalt), pick);
        const Bvh<T, W> bvh(d.s.view(), o);
        const Failure f = gen::check_structure(bvh, d.s.ray, d.s.view(), gen::exact_answers(d.s.ray, d.s.view()),
                                               d.choice(kLimitSalt));
        if (!f) return std::nullopt;
        return *f + "\n  options: leaf_size " + std::to_string(o.leaf_size) + ", bins " + std::to_string(o.bins);
    });
}

TYPED_TEST(BvhProps, BvhEqualsBruteForceW4) { bvh_equals_brute_force<TypeParam, 4>(); }
TYPED_TEST(BvhProps, BvhEqualsBruteForceW8) { bvh_equals_brute_force<TypeParam, 8>(); }

// Oracle-free: positions and direction scaled by 2^k (t unchanged) keep every exact
// t_enter, so the certified closest index is the same and each t the same or adjacent.
// k drawn from the case, halved until the scaling is exact; RapidCheck shrinks it
// towards ±1.
TYPED_TEST(BvhProps, CertifiedScalingKeepsIndex) {
    using T = TypeParam;
    run_scenes<T>([](const DrawnScene<T>& d, auto pick) -> Failure {
        constexpr int E = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent;
        const std::uint64_t c = d.choice(kScaleSalt);
        int k = ((c & 1) ? -1 : 1) * (1 + int((c >> 1) % std::uint64_t(E)));
        gen::Scene<T> scaled = d.s;
        while (!gen::scene_rescale(scaled, k, k) && k / 2 != 0) k /= 2;
        if (!gen::scene_rescale(scaled = d.s, k, k)) return std::nullopt;  // nothing scales it exactly
        k = pick(k, k < 0 ? -1 : 1);
        scaled = d.s;
        if (!gen::scene_rescale(scaled, k, k)) {
            RC_DISCARD("a shrunk exponent that does not scale exactly");
        }
        const Bvh<T, 8> a(d.s.view()), b(scaled.view());
        const ClosestHit<T> x = a.closest_hit(PreparedRay<T>(d.s.ray), certified);
        const ClosestHit<T> y = b.closest_hit(PreparedRay<T>(scaled.ray), certified);
        if (x.verdict == y.verdict && x.index == y.index && x.hit.face == y.hit.face &&
            (x.verdict != Verdict::hit ||
             (same_or_adjacent(x.hit.t_enter, y.hit.t_enter) && same_or_adjacent(x.hit.t_exit, y.hit.t_exit))))
            return std::nullopt;
        std::ostringstream os;
        os << "certified closest_hit " << to_string(x.verdict) << " index " << x.index << ' ' << x.hit
           << " but after scaling by 2^" << k << ": " << to_string(y.verdict) << " index " << y.index << ' ' << y.hit;
        return os.str();
    });
}

// The generators make what their names say, over 100 scenes each: same_t and duplicates
// give exact ties in t_enter between hit primitives (in some scenes), invalid gives
// invalid primitives in every scene, tiny at most 2 primitives, large at least 500.
TYPED_TEST(BvhProps, GeneratorsDeliver) {
    using T = TypeParam;
    for (const auto& g : gen::scene_generators<T>()) {
        int ties = 0, with_invalid = 0;
        std::size_t smallest = SIZE_MAX, largest = 0;
        for (std::uint64_t k = 1; k <= 100; ++k) {
            gen::Rng rng(k ^ gen::name_hash(g.name));
            const gen::Scene<T> s = g.make(rng);
            smallest = std::min(smallest, s.prims.size());
            largest = std::max(largest, s.prims.size());
            if (s.prims.size() > 200) continue;  // the oracle over every primitive: small scenes only
            const auto ex = gen::exact_answers(s.ray, s.view());
            bool tie = false, invalid = false;
            for (std::size_t i = 0; i < ex.size(); ++i) {
                invalid = invalid || (ex[i].verdict == Verdict::invalid && oracle::valid(s.ray));
                for (std::size_t j = i + 1; j < ex.size() && !tie; ++j)
                    tie = ex[i].verdict == Verdict::hit && ex[j].verdict == Verdict::hit &&
                          compare(ex[i].t_enter, ex[j].t_enter) == 0;
            }
            ties += tie;
            with_invalid += invalid;
        }
        std::cout << g.name << ": scenes with an exact tie " << ties << ", with an invalid primitive " << with_invalid
                  << ", sizes " << smallest << ".." << largest << '\n';
        if (g.name == "same_t" || g.name == "duplicates") {
            EXPECT_GE(ties, 30) << g.name;
        }
        if (g.name == "invalid") {
            EXPECT_GE(with_invalid, 60) << g.name;  // a fourth break the ray instead
        } else {
            EXPECT_EQ(with_invalid, 0) << g.name;
        }
        if (g.name == "tiny") {
            EXPECT_LE(largest, 2u);
        }
        if (g.name == "large") {
            EXPECT_GE(smallest, 500u);
        }
    }
}

// The oracle's exact order (oracle::compare) on values whose order is known: a sphere
// root against the rationals around it, roots of one quadratic, infinities.
TEST(OracleCompare, OrdersRootsRationalsAndInfinities) {
    // The ray from the origin along +x: the ball |p - (3, 1, 0)| <= 2 is entered at
    // 3 - sqrt(3) = 1.2679... (irrational) and left at 3 + sqrt(3); the boxes from
    // x = 1.25 and x = 1.3125 are entered there.
    const Ray<double> ray{Vec3<double>(0, 0, 0), Vec3<double>(1, 0, 0)};
    const auto s = oracle::exact(ray, Sphere<double>{Vec3<double>(3, 1, 0), 2});
    const auto b1 = oracle::exact(ray, Aabb<double>{Vec3<double>(1.25, -1, -1), Vec3<double>(2, 1, 1)});
    const auto b2 = oracle::exact(ray, Aabb<double>{Vec3<double>(1.3125, -1, -1), Vec3<double>(2, 1, 1)});
    const auto line = oracle::exact(Ray<double>{Vec3<double>(0, 0, 0), Vec3<double>(1, 0, 0), -std::numeric_limits<double>::infinity()},
                                    Plane<double>{Vec3<double>(0, 1, 0), 0});
    ASSERT_EQ(s.verdict, Verdict::hit);
    ASSERT_EQ(line.verdict, Verdict::hit);
    // 3 - sqrt(3) = 1.2679...: above 1.25, below 1.3125.
    EXPECT_EQ(compare(s.t_enter, b1.t_enter), 1);
    EXPECT_EQ(compare(b1.t_enter, s.t_enter), -1);
    EXPECT_EQ(compare(s.t_enter, b2.t_enter), -1);
    EXPECT_EQ(compare(s.t_enter, s.t_enter), 0);
    EXPECT_EQ(compare(s.t_enter, s.t_exit), -1);
    EXPECT_EQ(compare(s.t_exit, s.t_enter), 1);
    EXPECT_EQ(compare(line.t_enter, s.t_enter), -1);  // -inf: the ray lies in the plane
    EXPECT_EQ(compare(line.t_exit, s.t_exit), 1);     // +inf
    EXPECT_EQ(compare(line.t_enter, line.t_enter), 0);
    // Two different irrational roots: centre (3, 1, 0) radius 2 (3 - sqrt 3) against
    // centre (3, 0, 1) radius 2 (the same value) and (3, 2, 0) radius 3 (3 - sqrt 5).
    const auto s2 = oracle::exact(ray, Sphere<double>{Vec3<double>(3, 0, 1), 2});
    const auto s3 = oracle::exact(ray, Sphere<double>{Vec3<double>(3, 2, 0), 3});
    EXPECT_EQ(compare(s.t_enter, s2.t_enter), 0);
    EXPECT_EQ(compare(s3.t_enter, s.t_enter), -1);  // 0.76 < 1.27
    EXPECT_EQ(compare(s3.t_exit, s.t_exit), 1);     // 5.24 > 4.73
}

}  // namespace
