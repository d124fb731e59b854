// Large scenes: 100,000 generated objects parse, every one of them read back (its time
// is recorded as the test property parse_seconds, never asserted: speed belongs to the
// benchmarks), and their BVH fits in the estimate of render_need; the memory bounds of memory.hpp hold against what the JSON tree really
// takes; a scene that cannot fit in the memory left under RLIMIT_AS is refused, before
// it is parsed or rendered, with a message naming the need and what is available, and a
// clean exit status 1; progress lines appear only after a second and never in the image.
#include "render_support.hpp"

#include <rayproof/cli.hpp>
#include <rayproof/render/cli.hpp>
#include <rayproof/render/memory.hpp>
#include <rayproof/render/progress.hpp>

#include <nlohmann/json.hpp>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace rayproof::render::testing {
namespace {

void write_file(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    ASSERT_TRUE(f.good()) << "cannot write " << path;
}

TEST(Scale, ParsesOneHundredThousandObjects) {
    const std::uint64_t seed = 20261203;
    const GeneratedScene g = generated_scene(100'000, seed);
    const auto t0 = std::chrono::steady_clock::now();
    const ParseResult r = parse_scene(g.text, "generated.json");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    RecordProperty("parse_seconds", std::to_string(seconds));
    RecordProperty("scene_bytes", std::to_string(g.text.size()));
    ASSERT_TRUE(r) << "seed " << seed << ": " << r.error.to_string();
    const Scene& s = *r.scene;
    ASSERT_EQ(s.objects.size(), 100'000u) << "seed " << seed;
    EXPECT_EQ(s.materials.size(), 4u);
    EXPECT_EQ(s.lights.size(), 2u);
    // Every object is read as the kind it was written as.
    std::size_t mismatched = 0;
    for (std::size_t i = 0; i < g.kinds.size(); ++i) {
        const Shape& sh = s.objects[i].shape;
        const std::string& k = g.kinds[i];
        const bool ok = (k == "sphere" && std::holds_alternative<Sphere<double>>(sh)) ||
                        ((k == "box" || k == "cube") && std::holds_alternative<Aabb<double>>(sh)) ||
                        (k == "oriented_box" && std::holds_alternative<Obb<double>>(sh)) ||
                        (k == "plane" && std::holds_alternative<Plane<double>>(sh)) ||
                        (k == "polyhedron" && std::holds_alternative<Polyhedron>(sh) &&
                         !std::get<Polyhedron>(sh).planes.empty());
        if (!ok && mismatched++ < 5) ADD_FAILURE() << "seed " << seed << ": object " << i << " is not a " << k;
    }
    EXPECT_EQ(mismatched, 0u);
    // The BVH the tracer builds over them fits in render_need's estimate.
    const std::vector<Primitive<double>> prims = scene_primitives(s);
    const Bvh<double, scene_bvh_width> bvh(prims);
    const BvhStats st = bvh.stats();
    std::uint64_t estimate = 0;
    for (const auto& p : render_need(s, 1).parts)
        if (std::string(p.what) == "BVH") estimate = p.bytes;
    RecordProperty("bvh_bytes", std::to_string(st.bytes));
    RecordProperty("bvh_nodes", std::to_string(st.nodes));
    EXPECT_LE(st.bytes + prims.size() * sizeof(Primitive<double>), estimate) << st.nodes << " nodes";
}

// Heap bytes in use (glibc's count); 0 growth for a 1 MB block means the count is not
// available here (another allocator, e.g. a sanitizer's), and the test is skipped.
std::size_t heap_in_use() {
    const struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;
}

// scene_text_need bounds the JSON tree nlohmann-json builds, on a real scene and on texts
// made of the tokens that cost the most per byte.
TEST(Scale, TreeBoundHoldsOnCostlyTexts) {
    {
        // Through a volatile pointer, so that no compiler may elide the allocation.
        static void* volatile probe = nullptr;
        const std::size_t before = heap_in_use();
        probe = std::malloc(1 << 20);
        const bool counted = heap_in_use() >= before + (1 << 20);
        std::free(probe);
        if (!counted) GTEST_SKIP() << "glibc's mallinfo2 does not count this heap";
    }
    std::vector<std::pair<std::string, std::string>> texts;
    texts.push_back({"generated 20,000 objects", generated_scene(20'000, 7).text});
    const auto repeat = [](const std::string& item, int n) {
        std::string s = "[";
        for (int i = 0; i < n; ++i) s += (i ? "," : "") + item;
        return s + "]";
    };
    for (const char* item : {"{}", "[[]]", "[]", "{\"\":[]}", "{\"a\":0,\"b\":0}", "0", "\"\"",
                             "\"a string longer than fifteen bytes\"", "{\"a key longer than fifteen bytes\":{}}"})
        texts.push_back({item, repeat(item, 100'000)});
    for (const auto& [what, text] : texts) {
        const MemoryNeed need = scene_text_need(text);
        std::uint64_t tree_bound = 0;
        for (const auto& p : need.parts)
            if (std::string(p.what) == "JSON tree") tree_bound = p.bytes;
        const std::size_t before = heap_in_use();
        const nlohmann::json j = nlohmann::json::parse(text);
        const std::size_t used = heap_in_use() - before;
        EXPECT_LE(used, tree_bound) << what << ": " << text.size() << " bytes of text";
        EXPECT_GT(used, tree_bound / 4) << what << ": the bound is needlessly loose";
    }
}

// The refusal names the need, its parts and the limits found.
TEST(Scale, RefusalNamesNeedAndAvailable) {
    MemoryNeed need;
    need.parts = {{"image", 3'000'000'000}, {"thread stacks", 16'000'000}};
    MemoryAvailable avail{1'500'000'000, "MemAvailable 1.50 GB"};
    const std::string m = refusal(need, avail, "render it");
    EXPECT_EQ(m, "needs about 3.02 GB (image 3.00 GB, thread stacks 16.0 MB) to render it, but only 1.50 GB are "
                 "available (MemAvailable 1.50 GB)");
    avail.bytes = 3'016'000'000;
    EXPECT_EQ(refusal(need, avail, "render it"), "");
    const MemoryAvailable here = available_memory();
    EXPECT_GT(here.bytes, 0u) << here.how;
    EXPECT_NE(here.how.find("MemAvailable"), std::string::npos) << here.how;
}

// `rayproof args...` in a child process whose address space is limited to what it uses
// now plus `headroom` bytes: its exit status and its stderr.
std::pair<int, std::string> run_limited(std::vector<std::string> args, std::uint64_t headroom) {
    int fds[2];
    if (::pipe(fds) != 0) return {-1, "pipe failed"};
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(fds[0]);
        ::dup2(fds[1], STDERR_FILENO);
        std::uint64_t pages = 0;
        std::ifstream statm("/proc/self/statm");
        statm >> pages;
        const rlimit rl{rlim_t(pages * std::uint64_t(::sysconf(_SC_PAGESIZE)) + headroom),
                        rlim_t(pages * std::uint64_t(::sysconf(_SC_PAGESIZE)) + headroom)};
        if (pages == 0 || ::setrlimit(RLIMIT_AS, &rl) != 0) ::_exit(99);
        args.insert(args.begin(), "rayproof");
        std::vector<const char*> argv;
        for (const auto& a : args) argv.push_back(a.c_str());
        CLI::App app{"test", "rayproof"};
        app.require_subcommand(1);
        int status = 0;
        add_commands(app, status);
        if (const auto stop = rayproof::cli::parse(app, int(argv.size()), argv.data())) status = *stop;
        std::fflush(nullptr);
        ::_exit(status);
    }
    ::close(fds[1]);
    std::string err;
    char buf[4096];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) err.append(buf, std::size_t(n));
    ::close(fds[0]);
    int wstatus = 0;
    ::waitpid(pid, &wstatus, 0);
    if (!WIFEXITED(wstatus)) return {-2, err + " (killed by signal " + std::to_string(WTERMSIG(wstatus)) + ")"};
    return {WEXITSTATUS(wstatus), err};
}

// An image of 16384 x 4096 pixels (201 MB) with 64 MB of address space left: refused
// before the image is allocated, the output never written.
TEST(Scale, HugeImageRefusedUnderAddressSpaceLimit) {
    const std::string scene = scratch("scene.json"), out = scratch("out.png");
    write_file(scene, R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        "render": {"width": 16384, "height": 4096},
        "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"diffuse": 1}}]})");
    std::remove(out.c_str());
    const auto [status, err] = run_limited({"render", scene, "-o", out, "--threads", "1"}, 64u << 20);
    EXPECT_EQ(status, 1) << err;
    EXPECT_NE(err.find("needs about"), std::string::npos) << err;
    EXPECT_NE(err.find("image 201.3 MB"), std::string::npos) << err;
    EXPECT_NE(err.find("to render it, but only"), std::string::npos) << err;
    EXPECT_NE(err.find("RLIMIT_AS"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(out));
    std::remove(scene.c_str());
}

// 100,000 objects with 16 MB of address space left: refused before the text is parsed.
TEST(Scale, LargeSceneRefusedBeforeParsing) {
    const std::string scene = scratch("scene.json"), out = scratch("out.png");
    write_file(scene, generated_scene(100'000, 11).text);
    const auto [status, err] = run_limited({"render", scene, "-o", out, "--threads", "1"}, 64u << 20);
    EXPECT_EQ(status, 1) << err;
    EXPECT_NE(err.find(scene + ": needs about"), std::string::npos) << err;
    EXPECT_NE(err.find("JSON tree"), std::string::npos) << err;
    EXPECT_NE(err.find("to parse it, but only"), std::string::npos) << err;
    EXPECT_NE(err.find("RLIMIT_AS"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(out));
    // With room enough, the same file loads.
    const ParseResult r = load_scene(scene);
    ASSERT_TRUE(r) << r.error.to_string();
    EXPECT_EQ(r.scene->objects.size(), 100'000u);
    std::remove(scene.c_str());
}

std::string read_all(std::FILE* f) {
    std::rewind(f);
    std::string s;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
    return s;
}

// Nothing in the first second; then the phase's bar, and a line end when it finishes.
// Only the lower bound is a matter of time (the reporter cannot draw before a second has
// passed since construction); the test waits for the bar however late a loaded machine
// schedules the reporter, so it cannot fail by being slow.
TEST(Scale, ProgressAfterOneSecond) {
    std::FILE* f = std::tmpfile();
    ASSERT_NE(f, nullptr);
    {
        const auto t0 = std::chrono::steady_clock::now();
        Progress p(true, f);
        p.phase("checking", 200);
        p.set(50);
        std::string s;
        for (int i = 0; i < 600 && s.empty(); ++i) {  // up to a minute
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            std::fflush(f);
            s = read_all(f);
            std::fseek(f, 0, SEEK_END);
            if (s.empty()) continue;
            EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1)) << s;
        }
        EXPECT_NE(s.find("\rchecking [##########..............................]  25%"), std::string::npos) << s;  // 50 of 200
        p.set(100);
        p.finish();
    }
    const std::string s = read_all(f);
    std::fclose(f);
    EXPECT_EQ(s.back(), '\n') << s;
    // A disabled Progress writes nothing.
    std::FILE* g = std::tmpfile();
    ASSERT_NE(g, nullptr);
    {
        Progress p(false, g);
        p.phase("checking", 10);
        std::this_thread::sleep_for(std::chrono::milliseconds(1200));
        p.set(5);
        p.finish();
    }
    EXPECT_EQ(read_all(g), "");
    std::fclose(g);
}

}  // namespace
}  // namespace rayproof::render::testing
