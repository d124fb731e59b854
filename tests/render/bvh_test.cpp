// The tracer with its BVH against the tracer asking every object (TraceOptions::bvh off):
// seeded random scenes (every kind of object, planes and polyhedra beside and in the
// tree, glass whose shadows multiply transparencies, a visible light, exact duplicates of
// objects whose ties the lowest index must win) and the example scenes, rendered both
// ways. Certified: 0 differing pixels, and the same rays traced (the same ray tree).
// Fast and conservative promise no agreement; their differing pixels are recorded as the
// test properties differing_fast and differing_conservative, not asserted.
#include "render_support.hpp"

#include <string>

namespace rayproof::render::testing {
namespace {

RenderResult render_both(const Scene& s, bool bvh, int threads = 2) {
    RenderOptions opt;
    opt.threads = threads;
    opt.trace.bvh = bvh;
    return render(s, opt);
}

// A random scene of n objects in a cube of side `spread`, with `duplicates` exact copies
// of random earlier objects appended (another material: the tie goes to the first).
Scene random_scene(std::uint64_t seed, std::size_t n, double spread, std::size_t duplicates) {
    Scene s = parse_or_die(generated_scene(n, seed, spread).text);
    std::mt19937_64 rng(seed ^ 0x5eed);
    for (std::size_t k = 0; k < duplicates && !s.objects.empty(); ++k) {
        Object o = s.objects[std::uniform_int_distribution<std::size_t>(0, s.objects.size() - 1)(rng)];
        o.material = int((std::size_t(o.material) + 1) % s.materials.size());
        s.objects.push_back(o);
    }
    return s;
}

void expect_same_rays(const Stats& a, const Stats& b, const std::string& what) {
    EXPECT_EQ(a.primary, b.primary) << what;
    EXPECT_EQ(a.shadow, b.shadow) << what;
    EXPECT_EQ(a.reflection, b.reflection) << what;
    EXPECT_EQ(a.refraction, b.refraction) << what;
    EXPECT_EQ(a.culled, b.culled) << what;
    EXPECT_EQ(a.shadowed, b.shadowed) << what;
}

TEST(Bvh, RandomScenesCertifiedEqualBruteForce) {
    const std::uint64_t base = 20261203;
    long long differing[3] = {0, 0, 0};
    for (std::uint64_t k = 0; k < 8; ++k) {
        const std::uint64_t seed = base + k;
        const std::size_t n = 40 + 40 * k;
        Scene s = random_scene(seed, n, 6 + 2 * double(k), 6);
        s.settings.width = 48;
        s.settings.height = 36;
        s.settings.depth = 4;
        for (const Mode m : all_modes) {
            s.settings.mode = m;
            const RenderResult with = render_both(s, true), without = render_both(s, false);
            const ImageComparison c = compare(with.image, without.image);
            differing[int(m)] += c.differing_pixels;
            if (m != Mode::certified) continue;
            const std::string what = "seed " + std::to_string(seed) + ", " + std::to_string(s.objects.size()) + " objects";
            EXPECT_EQ(c.differing_pixels, 0) << what << ": largest channel difference " << c.max_channel_difference;
            expect_same_rays(with.stats, without.stats, what);
            EXPECT_LE(with.stats.kernel_queries, without.stats.kernel_queries) << what;
        }
    }
    RecordProperty("differing_fast", std::to_string(differing[int(Mode::fast)]));
    RecordProperty("differing_conservative", std::to_string(differing[int(Mode::conservative)]));
}

// The example scenes, certified, with and without the BVH.
TEST(Bvh, ExampleScenesCertifiedEqualBruteForce) {
    for (const char* name : {"default.json", "cube.json", "notes.json", "hostile.json", "polyhedra.json"}) {
        Scene s = load_or_die(scene_path(name));
        s.settings.width = 64;
        s.settings.height = 48;
        s.settings.mode = Mode::certified;
        const RenderResult with = render_both(s, true), without = render_both(s, false);
        EXPECT_TRUE(with.image.rgb == without.image.rgb) << name;
        expect_same_rays(with.stats, without.stats, name);
    }
}

// radiance() builds its own BVH: the same colour as asking every object.
TEST(Bvh, RadianceEqualsBruteForce) {
    Scene s = random_scene(7, 120, 8, 4);
    s.settings.mode = Mode::certified;
    TraceOptions with, without;
    without.bvh = false;
    for (double px : {10.5, 160.5, 301.25})
        for (double py : {5.5, 120.5, 230.75})
            EXPECT_TRUE(same_color(radiance(s, px, py, with), radiance(s, px, py, without))) << px << ", " << py;
}

}  // namespace
}  // namespace rayproof::render::testing
