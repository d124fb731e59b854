// The `render` and `export-pov` subcommands, run in-process: a render to PPM and PNG at
// the size asked for, option overrides, --diff between two modes, exit statuses for
// usage errors (2, with a message naming the option) and for bad scenes or files (1),
// and --help.
#include "render_support.hpp"

#include <rayproof/cli.hpp>
#include <rayproof/render/cli.hpp>

#include <fstream>
#include <sstream>

namespace rayproof::render::testing {
namespace {

// `rayproof args...` with the subcommands of the render library, as tools/ builds it.
int run(std::vector<std::string> args) {
    args.insert(args.begin(), "rayproof");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    CLI::App app{"test", "rayproof"};
    app.require_subcommand(1);
    int status = 0;
    add_commands(app, status);
    if (const auto stop = rayproof::cli::parse(app, int(argv.size()), argv.data())) return *stop;
    return status;
}

int render_cmd(std::vector<std::string> args) {
    args.insert(args.begin(), "render");
    return run(std::move(args));
}

// The exit status and what went to stderr.
std::pair<int, std::string> render_err(std::vector<std::string> args) {
    ::testing::internal::CaptureStderr();
    const int status = render_cmd(std::move(args));
    return {status, ::testing::internal::GetCapturedStderr()};
}

TEST(Cli, RendersPpmAndPngAtTheRequestedSize) {
    for (const char* ext : {"ppm", "png"}) {
        const std::string out = scratch(std::string("out.") + ext);
        ASSERT_EQ(render_cmd({scene_path("cube.json"), "-o", out, "--width", "16", "--height", "12", "--mode",
                              mode_name(every_mode().back()), "--depth", "2", "--threads", "2", "-q"}),
                  0);
        Image img;
        ASSERT_EQ(read_image(out, img), "");
        EXPECT_EQ(img.width, 16);
        EXPECT_EQ(img.height, 12);
    }
}

TEST(Cli, DiffWritesAPictureOfTheDisagreement) {
    const auto modes = every_mode();
    if (modes.size() < 2) GTEST_SKIP() << "only one mode in this build";
    const std::string out = scratch("diff.png");
    ASSERT_EQ(render_cmd({scene_path("hostile.json"), "--diff", mode_name(modes.front()), mode_name(modes.back()),
                          "-o", out, "--width", "32", "--height", "24"}),
              0);
    Image img;
    ASSERT_EQ(read_image(out, img), "");
    EXPECT_EQ(img.width, 32);
}

TEST(Cli, UsageErrorsExitWith2) {
    const std::string scene = scene_path("cube.json"), out = scratch("x.png");
    EXPECT_EQ(render_cmd({scene}), 2);                                    // no -o
    EXPECT_EQ(render_cmd({"-o", out}), 2);                                // no scene
    EXPECT_EQ(render_cmd({scene, "-o", scratch("x.gif")}), 2);            // unknown format
    EXPECT_EQ(render_cmd({scene, "-o", out, "--width", "abc"}), 2);       // not a number
    EXPECT_EQ(render_cmd({scene, "-o", out, "--width", "0"}), 2);         // out of range
    EXPECT_EQ(render_cmd({scene, "-o", out, "--mode", "exact"}), 2);      // no such mode
    EXPECT_EQ(render_cmd({scene, "-o", out, "--frobnicate"}), 2);         // unknown option
    EXPECT_EQ(render_cmd({scene, "-o", out, "--diff", "fast"}), 2);       // --diff needs two modes
    EXPECT_EQ(render_cmd({scene, scene, "-o", out}), 2);                  // two scenes
    EXPECT_EQ(render_cmd({scene, "-o", out, "--depth"}), 2);              // no value
    EXPECT_EQ(run({"frobnicate"}), 2);                                    // no such subcommand
    EXPECT_EQ(render_cmd({"--help"}), 0);
    EXPECT_EQ(run({"export-pov", "--help"}), 0);
}

TEST(Cli, UsageErrorsNameTheOptionAndShowTheUsage) {
    const std::string scene = scene_path("cube.json"), out = scratch("x.png");
    for (const auto& [args, named] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{scene, "-o", out, "--width", "abc"}, "--width"},
             {{scene, "-o", out, "--frobnicate"}, "--frobnicate"},
             {{scene, "-o", out, "--mode", "exact"}, "--mode"},
             {{scene, "-o", out, "--depth"}, "--depth"},
             {{scene}, "--output"}}) {
        const auto [status, err] = render_err(args);
        EXPECT_EQ(status, 2) << named;
        EXPECT_EQ(err.rfind("rayproof render: ", 0), 0u) << err;
        EXPECT_NE(err.substr(0, err.find('\n')).find(named), std::string::npos) << err;
        EXPECT_NE(err.find("Usage: rayproof render [OPTIONS] SCENE"), std::string::npos) << err;
    }
}

TEST(Cli, HelpNamesEveryOption) {
    ::testing::internal::CaptureStdout();
    ASSERT_EQ(render_cmd({"--help"}), 0);
    const std::string help = ::testing::internal::GetCapturedStdout();
    for (const char* o : {"--output", "--width", "--height", "--mode", "--depth", "--supersample", "--threads", "--diff",
                          "--diff-threshold", "--stats", "--quiet", "--help"})
        EXPECT_NE(help.find(o), std::string::npos) << o;
}

TEST(Cli, BadScenesAndFilesExitWith1) {
    const std::string bad = scratch("bad.json");
    std::ofstream(bad) << "{\"camera\": }";
    EXPECT_EQ(render_cmd({bad, "-o", scratch("x.png")}), 1);
    EXPECT_EQ(render_cmd({scratch("missing.json"), "-o", scratch("x.png")}), 1);
    EXPECT_EQ(render_cmd({scene_path("cube.json"), "-o", "/nonexistent/dir/x.png", "--width", "4", "--height", "3"}), 1);
}

TEST(Cli, ExportPovWritesAFile) {
    const std::string out = scratch("scene.pov");
    ASSERT_EQ(run({"export-pov", scene_path("default.json"), "-o", out}), 0);
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("#version 3.7;"), std::string::npos);
    EXPECT_EQ(run({"export-pov"}), 2);
    EXPECT_EQ(run({"export-pov", scratch("missing.json")}), 1);
}

}  // namespace
}  // namespace rayproof::render::testing
