// The `render`, `export-pov` and `compare` subcommands, run in-process: a render to PPM
// and PNG at the size asked for, option overrides, --diff between two modes, exit statuses
// for usage errors (2, with a message naming the option) and for bad scenes or files (1),
// and --help; the output path checked before any ray is traced (and no file left behind
// by the check), a directory as the scene, and write failures on a full device (/dev/full)
// reported with their reason, for images, the POV-Ray file and standard output; the mean
// absolute difference `compare` prints.
#include "render_support.hpp"

#include <rayproof/cli.hpp>
#include <rayproof/render/cli.hpp>

#include <fcntl.h>
#include <stdio_ext.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
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

std::pair<int, std::string> run_err(std::vector<std::string> args) {
    ::testing::internal::CaptureStderr();
    const int status = run(std::move(args));
    return {status, ::testing::internal::GetCapturedStderr()};
}

// run(args) with the standard output sent to `device`; what could not be written is dropped.
int run_with_stdout_on(const char* device, std::vector<std::string> args) {
    std::fflush(stdout);
    const int saved = ::dup(STDOUT_FILENO);
    const int fd = ::open(device, O_WRONLY);
    if (saved < 0 || fd < 0) {
        ADD_FAILURE() << "cannot redirect the standard output to " << device << ": " << std::strerror(errno);
        return -1;
    }
    ::dup2(fd, STDOUT_FILENO);
    ::close(fd);
    const int status = run(std::move(args));
    __fpurge(stdout);
    ::dup2(saved, STDOUT_FILENO);
    ::close(saved);
    std::clearerr(stdout);
    return status;
}

std::string reason(int error) { return std::strerror(error); }

// `--diff A B` with the first and the last mode.
const std::vector<std::string> diff_args = {"--diff", mode_name(every_mode().front()), mode_name(every_mode().back())};

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

// A render that takes seconds (about 3.5 s on one core of a 2020s machine, twice that with
// --diff), so that a check made after rendering shows in the time taken.
std::vector<std::string> long_render(const std::string& out) {
    return {scene_path("default.json"), "-o", out, "--width", "800", "--height", "600", "--supersample", "2",
            "--threads", "1", "-q"};
}

// Output paths that cannot be written fail at once, naming the path and the reason, for
// the image and for the --diff picture; each reason is what the system says when the
// path is opened for writing.
TEST(Cli, OutputPathIsCheckedBeforeRendering) {
    const std::filesystem::path dir = scratch("dir");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "already.png");
    std::vector<std::pair<std::string, std::string>> cases = {
        {(dir / "missing" / "x.png").string(), reason(ENOENT)},      // a missing directory
        {(dir / "already.png").string(), reason(EISDIR)},            // a directory
        {scene_path("cube.json") + "/x.png", reason(ENOTDIR)},        // a file taken for a directory
    };
    // An unwritable location: a read-only directory (no obstacle to root), and sysfs,
    // where nobody creates files; each where the system does refuse it.
    const std::filesystem::path ro = dir / "read-only";
    std::filesystem::create_directory(ro);
    std::filesystem::permissions(ro, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    for (const std::string& p : {(ro / "x.png").string(), std::string("/sys/rayproof-render-test.png")}) {
        const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            ::close(fd);
            ::unlink(p.c_str());
        } else {
            cases.push_back({p, reason(errno)});
        }
    }
    for (const auto& [out, why] : cases) {
        for (bool diff : {false, true}) {
            std::vector<std::string> args = long_render(out);
            if (diff) args.insert(args.end(), diff_args.begin(), diff_args.end());
            const auto start = std::chrono::steady_clock::now();
            const auto [status, err] = render_err(args);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            EXPECT_EQ(status, 1) << out;
            EXPECT_EQ(err, "rayproof render: cannot write '" + out + "': " + why + "\n");
            EXPECT_LT(seconds, 1.0) << out << ": the check came after rendering";
        }
    }
    std::filesystem::permissions(ro, std::filesystem::perms::owner_all);
    std::filesystem::remove_all(dir);
}

// The check creates a new output file to see that it can; it removes it again, so a
// render that fails afterwards (here: on the scene) leaves no empty file behind.
TEST(Cli, OutputCheckLeavesNoFileBehind) {
    const std::string out = scratch("new.png"), bad = scratch("bad.json");
    std::filesystem::remove(out);
    std::ofstream(bad) << R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": 1})";
    const auto [status, err] = render_err({bad, "-o", out});
    EXPECT_EQ(status, 1);
    EXPECT_NE(err.find("objects: expected an array"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(out));
    // And an existing file is opened without being truncated.
    std::ofstream(out) << "keep";
    EXPECT_EQ(render_err({bad, "-o", out}).first, 1);
    EXPECT_EQ(std::filesystem::file_size(out), 4u);
    std::filesystem::remove(out);
}

// A character device passes the check: an image can be written to /dev/null.
TEST(Cli, DevicesAreValidOutputs) {
    if (!std::filesystem::exists("/dev/null")) GTEST_SKIP() << "no /dev/null";
    const std::filesystem::path link = scratch("null.png");
    std::filesystem::remove(link);
    std::filesystem::create_symlink("/dev/null", link);
    EXPECT_EQ(render_cmd({scene_path("cube.json"), "-o", link.string(), "--width", "4", "--height", "3", "-q"}), 0);
    EXPECT_TRUE(std::filesystem::is_symlink(link));
    std::filesystem::remove(link);
}

TEST(Cli, ADirectoryAsTheSceneSaysSo) {
    const std::string dir = std::string(RAYPROOF_SCENES_DIR);
    const auto [status, err] = render_err({dir, "-o", scratch("x.png")});
    EXPECT_EQ(status, 1);
    EXPECT_EQ(err, "rayproof render: " + dir + ": is a directory, not a scene file\n");
}

// A full device: every writer reports "No space left on device" and exits 1. (The
// exports turn the tree attenuation off, so that the error is all export-pov says.)
TEST(Cli, WriteFailuresSayWhy) {
    if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    const std::string full = reason(ENOSPC);
    auto [status, err] =
        run_err({"export-pov", scene_path("default.json"), "--no-tree-attenuation", "-o", "/dev/full"});
    EXPECT_EQ(status, 1);
    EXPECT_EQ(err, "rayproof export-pov: cannot write '/dev/full': " + full + "\n");

    ::testing::internal::CaptureStderr();
    status = run_with_stdout_on("/dev/full", {"export-pov", scene_path("default.json"), "--no-tree-attenuation"});
    err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(status, 1);
    EXPECT_EQ(err, "rayproof export-pov: cannot write to standard output: " + full + "\n");

    const std::filesystem::path dir = scratch("full");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directory(dir);
    for (const char* name : {"full.png", "full.ppm"}) {
        const std::string link = (dir / name).string();
        std::filesystem::create_symlink("/dev/full", link);
        for (bool diff : {false, true}) {
            std::vector<std::string> args = {scene_path("cube.json"), "-o", link, "--width", "64", "--height", "48"};
            if (diff) args.insert(args.end(), diff_args.begin(), diff_args.end());
            std::tie(status, err) = render_err(args);
            EXPECT_EQ(status, 1) << link;
            EXPECT_EQ(err, "rayproof render: cannot write '" + link + "': " + full + "\n");
        }
    }
    std::filesystem::remove_all(dir);
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

// What the export cannot write exactly goes to stderr, one "not exact" line each, and
// the export still succeeds; with the tree attenuation off the default scene has none.
TEST(Cli, ExportPovSaysWhatIsNotExact) {
    const std::string out = scratch("scene.pov");
    auto [status, err] = run_err({"export-pov", scene_path("default.json"), "-o", out});
    EXPECT_EQ(status, 0);
    EXPECT_EQ(err.rfind("rayproof export-pov: not exact: the ray tree's distance attenuation", 0), 0u) << err;
    std::tie(status, err) = run_err({"export-pov", scene_path("default.json"), "-o", out, "--no-tree-attenuation"});
    EXPECT_EQ(status, 0);
    EXPECT_EQ(err, "");
}

// `rayproof compare A B`: 0 for an image and itself; the mean over every channel for two
// images that differ by a known amount; status 1 for different sizes.
TEST(Cli, CompareGivesTheMeanAbsoluteDifference) {
    const auto compare_cmd = [](const std::string& a, const std::string& b, std::string& out) {
        ::testing::internal::CaptureStdout();
        ::testing::internal::CaptureStderr();
        const int status = run({"compare", a, b});
        out = ::testing::internal::GetCapturedStdout() + ::testing::internal::GetCapturedStderr();
        return status;
    };
    Image a(4, 2), b(4, 2), c(3, 2);
    for (std::size_t i = 0; i < b.rgb.size(); ++i) b.rgb[i] = std::uint8_t(i % 3 == 0 ? 6 : 0);  // red +6
    const std::string pa = scratch("a.png"), pb = scratch("b.ppm"), pc = scratch("c.png");
    ASSERT_EQ(write_image(a, pa), "");
    ASSERT_EQ(write_image(b, pb), "");
    ASSERT_EQ(write_image(c, pc), "");
    std::string out;
    EXPECT_EQ(compare_cmd(pa, pa, out), 0);
    EXPECT_NE(out.find("mean absolute difference 0.000/255"), std::string::npos) << out;
    EXPECT_EQ(compare_cmd(pa, pb, out), 0);
    EXPECT_NE(out.find("mean absolute difference 2.000/255"), std::string::npos) << out;
    EXPECT_NE(out.find("largest 6/255; 8 of 8 pixels differ"), std::string::npos) << out;
    EXPECT_EQ(compare_cmd(pa, pc, out), 1);
    EXPECT_NE(out.find("differ in size"), std::string::npos) << out;
}

}  // namespace
}  // namespace rayproof::render::testing
