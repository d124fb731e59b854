// `rayproof render` and `rayproof export-pov`: argument parsing, messages, files.
#include <rayproof/render/cli.hpp>

#include <rayproof/render/image.hpp>
#include <rayproof/render/parse.hpp>
#include <rayproof/render/pov.hpp>
#include <rayproof/render/tracer.hpp>

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

namespace rayproof::render {
namespace {

const char* const render_usage =
    "usage: rayproof render SCENE.json -o OUT.png|OUT.ppm [options]\n"
    "       rayproof render SCENE.json --diff MODE_A MODE_B -o DIFF.png [options]\n"
    "\n"
    "Renders a scene file (schema: render/scenes/README.md). Options override the\n"
    "scene's \"render\" settings:\n"
    "  -o, --output FILE   the image to write; .png or .ppm (binary P6) by extension\n"
    "  --width W           image width in pixels\n"
    "  --height H          image height in pixels\n"
    "  --mode M            kernel mode for every ray query: fast, conservative, certified\n"
    "  --depth N           longest ray path (1: primary and shadow rays only)\n"
    "  --supersample N     N x N rays per pixel\n"
    "  --threads T         worker threads (default: all cores)\n"
    "  --diff A B          render in modes A and B, write an image that highlights the\n"
    "                      pixels where they differ, and print how many\n"
    "  --diff-threshold N  with --diff: count a pixel only when a channel differs by\n"
    "                      more than N (of 255); default 0, any difference\n"
    "  --stats             print ray and kernel-query counts\n"
    "  -q, --quiet         print nothing on success\n"
    "  -h, --help          this text\n";

const char* const export_usage =
    "usage: rayproof export-pov SCENE.json [-o OUT.pov] [--width W --height H]\n"
    "\n"
    "Prints the scene as a POV-Ray 3.7 scene (on stdout, or into OUT.pov), e.g.\n"
    "  rayproof export-pov scene.json > scene.pov && povray +W320 +H240 scene.pov\n";

struct Args {
    std::string scene, output;
    std::optional<int> width, height, depth, supersample, threads;
    std::optional<Mode> mode;
    std::optional<Mode> diff_a, diff_b;
    int diff_threshold = 0;
    bool stats = false, quiet = false, help = false;
};

// Prints "rayproof CMD: msg" and returns the usage-error status.
int usage_error(const char* cmd, const std::string& msg) {
    std::fprintf(stderr, "rayproof %s: %s\n(rayproof %s --help for the options)\n", cmd, msg.c_str(), cmd);
    return 2;
}

std::optional<int> to_int(std::string_view s) {
    int v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
    return v;
}

// Parses argv into a; returns "" or an error message.
std::string parse_args(int argc, char** argv, bool render, Args& a) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        auto value = [&]() -> std::optional<std::string_view> {  // the option's argument
            if (i + 1 >= argc) return std::nullopt;
            return std::string_view(argv[++i]);
        };
        auto int_opt = [&](std::optional<int>& out, int lo, int hi) -> std::string {
            const auto v = value();
            if (!v) return std::string(arg) + " needs a value";
            const auto n = to_int(*v);
            if (!n || *n < lo || *n > hi)
                return std::string(arg) + " expects an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                       ", got '" + std::string(*v) + "'";
            out = *n;
            return "";
        };
        auto mode_opt = [&](std::optional<Mode>& out, const std::string& name) -> std::string {
            const auto v = value();
            if (!v) return name + " needs a mode";
            const auto m = parse_mode(*v);
            if (!m) return name + " expects fast, conservative or certified, got '" + std::string(*v) + "'";
            out = *m;
            return "";
        };
        std::string err;
        if (arg == "-h" || arg == "--help") {
            a.help = true;
        } else if (arg == "-o" || arg == "--output") {
            const auto v = value();
            if (!v) return std::string(arg) + " needs a file name";
            a.output = std::string(*v);
        } else if (arg == "--width") {
            err = int_opt(a.width, 1, 16384);
        } else if (arg == "--height") {
            err = int_opt(a.height, 1, 16384);
        } else if (render && arg == "--depth") {
            err = int_opt(a.depth, 1, 64);
        } else if (render && arg == "--supersample") {
            err = int_opt(a.supersample, 1, 16);
        } else if (render && arg == "--threads") {
            err = int_opt(a.threads, 1, 1024);
        } else if (render && arg == "--mode") {
            err = mode_opt(a.mode, "--mode");
        } else if (render && arg == "--diff") {
            err = mode_opt(a.diff_a, "--diff");
            if (err.empty()) err = mode_opt(a.diff_b, "--diff (second mode)");
        } else if (render && arg == "--diff-threshold") {
            std::optional<int> t;
            err = int_opt(t, 0, 254);
            if (t) a.diff_threshold = *t;
        } else if (render && arg == "--stats") {
            a.stats = true;
        } else if (render && (arg == "-q" || arg == "--quiet")) {
            a.quiet = true;
        } else if (!arg.empty() && arg[0] == '-') {
            return "unknown option '" + std::string(arg) + "'";
        } else if (a.scene.empty()) {
            a.scene = std::string(arg);
        } else {
            return "more than one scene file given ('" + a.scene + "' and '" + std::string(arg) + "')";
        }
        if (!err.empty()) return err;
    }
    return "";
}

std::optional<Scene> load(const Args& a, const char* cmd) {
    ParseResult r = load_scene(a.scene);
    if (!r) {
        std::fprintf(stderr, "rayproof %s: %s\n", cmd, r.error.to_string().c_str());
        return std::nullopt;
    }
    Scene s = std::move(*r.scene);
    if (a.width) s.settings.width = *a.width;
    if (a.height) s.settings.height = *a.height;
    if (a.depth) s.settings.depth = *a.depth;
    if (a.supersample) s.settings.supersample = *a.supersample;
    if (a.mode) s.settings.mode = *a.mode;
    if ((long long)s.settings.width * s.settings.height > (1LL << 26)) {
        std::fprintf(stderr, "rayproof %s: %d x %d pixels is too large\n", cmd, s.settings.width, s.settings.height);
        return std::nullopt;
    }
    return s;
}

void print_stats(const Stats& st) {
    std::fprintf(stderr,
                 "rays: %llu primary, %llu shadow, %llu reflected, %llu refracted; %llu not traced (below "
                 "min_contribution)\nkernel queries: %llu (%llu invalid); shadow rays fully blocked: %llu\n",
                 (unsigned long long)st.primary, (unsigned long long)st.shadow, (unsigned long long)st.reflection,
                 (unsigned long long)st.refraction, (unsigned long long)st.culled, (unsigned long long)st.kernel_queries,
                 (unsigned long long)st.invalid, (unsigned long long)st.shadowed);
}

int run_render(const Args& a) {
    if (a.scene.empty()) return usage_error("render", "no scene file given");
    if (a.output.empty()) return usage_error("render", "no output file given (-o OUT.png or -o OUT.ppm)");
    if (!has_image_extension(a.output))
        return usage_error("render", "cannot tell the image format of '" + a.output + "': use .png or .ppm");
    std::optional<Scene> scene = load(a, "render");
    if (!scene) return 1;

    RenderOptions opt;
    opt.threads = a.threads.value_or(0);
    opt.progress = !a.quiet && isatty(STDERR_FILENO);
    const int threads = opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));

    auto render_mode = [&](Mode m) {
        Scene s = *scene;
        s.settings.mode = m;
        return render(s, opt);
    };

    if (a.diff_a) {
        const auto ra = render_mode(*a.diff_a);
        const auto rb = render_mode(*a.diff_b);
        const ImageComparison c = compare(ra.image, rb.image, a.diff_threshold);
        if (const std::string e = write_image(diff_image(ra.image, rb.image, a.diff_threshold), a.output);
            !e.empty()) {
            std::fprintf(stderr, "rayproof render: %s\n", e.c_str());
            return 1;
        }
        const long long total = (long long)ra.image.width * ra.image.height;
        std::printf("%s vs %s: %lld of %lld pixels differ%s (%.3f%%), largest channel difference %d; wrote %s\n",
                    mode_name(*a.diff_a), mode_name(*a.diff_b), c.differing_pixels, total,
                    a.diff_threshold ? (" by more than " + std::to_string(a.diff_threshold)).c_str() : "",
                    100.0 * double(c.differing_pixels) / double(total), c.max_channel_difference, a.output.c_str());
        if (a.stats) {
            print_stats(ra.stats);
            print_stats(rb.stats);
        }
        return 0;
    }

    const auto r = render_mode(scene->settings.mode);
    if (const std::string e = write_image(r.image, a.output); !e.empty()) {
        std::fprintf(stderr, "rayproof render: %s\n", e.c_str());
        return 1;
    }
    if (!a.quiet)
        std::printf("wrote %s (%dx%d, mode %s, depth %d, %d thread%s, %.2f s)\n", a.output.c_str(), r.image.width,
                    r.image.height, mode_name(scene->settings.mode), scene->settings.depth, threads,
                    threads == 1 ? "" : "s", r.seconds);
    if (a.stats) print_stats(r.stats);
    return 0;
}

int run_export(const Args& a) {
    if (a.scene.empty()) return usage_error("export-pov", "no scene file given");
    const std::optional<Scene> scene = load(a, "export-pov");
    if (!scene) return 1;
    const std::string text = export_pov(*scene, a.scene);
    if (a.output.empty()) {
        std::fwrite(text.data(), 1, text.size(), stdout);
        return std::fflush(stdout) == 0 ? 0 : 1;
    }
    std::ofstream out(a.output, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
        std::fprintf(stderr, "rayproof export-pov: cannot write '%s'\n", a.output.c_str());
        return 1;
    }
    return 0;
}

}  // namespace
}  // namespace rayproof::render

int rayproof_cli_render(int argc, char** argv) {
    using namespace rayproof::render;
    try {
        Args a;
        if (const std::string e = parse_args(argc, argv, true, a); !e.empty()) return usage_error("render", e);
        if (a.help) {
            std::fputs(render_usage, stdout);
            return 0;
        }
        return run_render(a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rayproof render: %s\n", e.what());
        return 1;
    }
}

int rayproof_cli_export_pov(int argc, char** argv) {
    using namespace rayproof::render;
    try {
        Args a;
        if (const std::string e = parse_args(argc, argv, false, a); !e.empty()) return usage_error("export-pov", e);
        if (a.help) {
            std::fputs(export_usage, stdout);
            return 0;
        }
        return run_export(a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rayproof export-pov: %s\n", e.what());
        return 1;
    }
}
