// The threaded image loop: every example scene in every mode gives the same image, bit
// for bit, and the same ray and query counts whether it is rendered by one thread or by
// four (each thread takes the next free row and counts into its own Stats, summed at the
// end), and with the progress bar on, which a render this short never draws.
#include "render_support.hpp"

#include <algorithm>
#include <thread>

namespace rayproof::render::testing {
namespace {

struct Case {
    std::string scene;  // file name under render/scenes/, without .json
    Mode mode;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << "/" << mode_name(c.mode); }

RenderResult render_with(const Scene& s, int threads, bool progress = false) {
    RenderOptions opt;
    opt.threads = threads;
    opt.progress = progress;
    return render(s, opt);
}

void expect_same_counts(const Stats& a, const Stats& b) {
    EXPECT_EQ(a.primary, b.primary);
    EXPECT_EQ(a.shadow, b.shadow);
    EXPECT_EQ(a.reflection, b.reflection);
    EXPECT_EQ(a.refraction, b.refraction);
    EXPECT_EQ(a.kernel_queries, b.kernel_queries);
    EXPECT_EQ(a.invalid, b.invalid);
    EXPECT_EQ(a.culled, b.culled);
    EXPECT_EQ(a.shadowed, b.shadowed);
}

class Threads : public ::testing::TestWithParam<Case> {};

TEST_P(Threads, OneAndFourGiveTheSameImageAndCounts) {
    Scene s = load_or_die(scene_path(GetParam().scene + ".json"));
    s.settings.width = 61;  // not a multiple of anything the scheduler might split by
    s.settings.height = 47;
    s.settings.supersample = 2;
    s.settings.mode = GetParam().mode;
    const RenderResult one = render_with(s, 1), four = render_with(s, 4);
    EXPECT_EQ(one.threads, 1);
    EXPECT_EQ(four.threads, 4);
    ASSERT_EQ(one.image.width, 61);
    ASSERT_EQ(one.image.height, 47);
    EXPECT_TRUE(one.image.rgb == four.image.rgb) << compare(one.image, four.image).differing_pixels << " pixels differ";
    EXPECT_EQ(one.stats.primary, 61u * 47u * 4u);  // every sub-pixel ray counted once
    expect_same_counts(one.stats, four.stats);
    EXPECT_GT(one.stats.kernel_queries, one.stats.primary);
}

std::vector<Case> cases() {
    std::vector<Case> v;
    for (const char* s : {"default", "cube", "hostile", "notes"})
        for (Mode m : every_mode()) v.push_back({s, m});
    return v;
}

INSTANTIATE_TEST_SUITE_P(Scenes, Threads, ::testing::ValuesIn(cases()), [](const auto& info) {
    return info.param.scene + "_" + mode_name(info.param.mode);
});

// With progress on, the rows run on another thread while the calling one waits: the same
// image and counts, and nothing on stderr for a render under a second.
TEST(ThreadsProgress, SameImageAndSilentWhenShort) {
    Scene s = load_or_die(scene_path("default.json"));
    s.settings.width = 40;
    s.settings.height = 30;
    const RenderResult plain = render_with(s, 2);
    ::testing::internal::CaptureStderr();
    const RenderResult shown = render_with(s, 2, true);
    const std::string err = ::testing::internal::GetCapturedStderr();
    ASSERT_LT(shown.seconds, 1);
    EXPECT_EQ(err, "");
    EXPECT_TRUE(plain.image.rgb == shown.image.rgb);
    expect_same_counts(plain.stats, shown.stats);
}

// Zero threads means every hardware thread; there are never more threads than rows.
TEST(ThreadsProgress, ThreadCounts) {
    Scene s = load_or_die(scene_path("cube.json"));
    s.settings.width = 33;
    s.settings.height = 5;
    const int all = int(std::max(1u, std::thread::hardware_concurrency()));
    const RenderResult a = render_with(s, 0), b = render_with(s, 1), many = render_with(s, 1024);
    EXPECT_EQ(a.threads, std::min(all, 5));
    EXPECT_EQ(many.threads, 5);
    EXPECT_TRUE(many.image.rgb == b.image.rgb);
    EXPECT_TRUE(a.image.rgb == b.image.rgb);
    expect_same_counts(a.stats, b.stats);
    expect_same_counts(many.stats, b.stats);
    EXPECT_EQ(a.stats.primary, 33u * 5u);
}

}  // namespace
}  // namespace rayproof::render::testing
