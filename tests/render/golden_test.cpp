// Golden images: every example scene in every mode the kernel has, rendered at 64×48
// and compared with the picture the project rendered itself (tests/render/golden/),
// within a tolerance: PSNR >= 45 dB and at most 0.1% of the pixels with a channel off
// by more than 16 of 255 (room for a different compiler, not for a different picture).
// A render with the camera nudged must fail the same comparison, so the tolerance has
// teeth. RAYPROOF_UPDATE_GOLDEN=1 rewrites the golden files instead of comparing.
#include "render_support.hpp"

#include <cstdlib>
#include <filesystem>

namespace rayproof::render::testing {
namespace {

constexpr int gw = 64, gh = 48;

struct Case {
    std::string scene;  // file name under render/scenes/, without .json
    Mode mode;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << "/" << mode_name(c.mode); }

std::string golden_path(const Case& c) {
    return std::string(RAYPROOF_GOLDEN_DIR) + "/" + c.scene + "-" + mode_name(c.mode) + ".png";
}

Image render_small(Scene s, Mode mode) {
    s.settings.width = gw;
    s.settings.height = gh;
    s.settings.mode = mode;
    RenderOptions opt;
    opt.threads = 2;
    return render(s, opt).image;
}

// The acceptance rule; returns "" when `got` matches `want`.
std::string matches(const Image& got, const Image& want) {
    const ImageComparison c = compare(got, want, 16);
    if (!c.same_size) return "sizes differ";
    const long long allowed = (long long)want.width * want.height / 1000;
    if (c.psnr < 45 || c.differing_pixels > allowed)
        return "PSNR " + std::to_string(c.psnr) + " dB, " + std::to_string(c.differing_pixels) +
               " pixels off by more than 16 (allowed: PSNR >= 45, " + std::to_string(allowed) + " pixels)";
    return "";
}

class Golden : public ::testing::TestWithParam<Case> {};

TEST_P(Golden, MatchesWithinTolerance) {
    const Case c = GetParam();
    const Image img = render_small(load_or_die(scene_path(c.scene + ".json")), c.mode);
    const std::string path = golden_path(c);
    if (const char* u = std::getenv("RAYPROOF_UPDATE_GOLDEN"); u && std::string(u) == "1") {
        ASSERT_EQ(write_image(img, path), "");
        GTEST_SKIP() << "rewrote " << path;
    }
    Image want;
    ASSERT_EQ(read_image(path, want), "") << "(RAYPROOF_UPDATE_GOLDEN=1 creates it)";
    const std::string why = matches(img, want);
    if (!why.empty()) {
        const std::string out = scratch("got.png");
        (void)write_image(img, out);
        FAIL() << c.scene << " in " << mode_name(c.mode) << ": " << why << "; the render is in " << out;
    }
}

std::vector<Case> cases() {
    std::vector<Case> v;
    for (const char* s : {"default", "cube", "hostile", "notes"})
        for (Mode m : every_mode()) v.push_back({s, m});
    return v;
}

INSTANTIATE_TEST_SUITE_P(Scenes, Golden, ::testing::ValuesIn(cases()), [](const auto& info) {
    return info.param.scene + "_" + mode_name(info.param.mode);
});

// The same comparison rejects a picture that is only slightly different: the default
// scene with the eye moved 5 cm sideways (at 64×48 a pixel spans about 14 cm there).
TEST(GoldenTolerance, RejectsANudgedCamera) {
    const Mode mode = every_mode().back();
    Image want;
    ASSERT_EQ(read_image(golden_path({"default", mode}), want), "");
    Scene s = load_or_die(scene_path("default.json"));
    EXPECT_EQ(matches(render_small(s, mode), want), "");
    s.camera.position.x() += 0.05;
    EXPECT_NE(matches(render_small(s, mode), want), "");
}

}  // namespace
}  // namespace rayproof::render::testing
