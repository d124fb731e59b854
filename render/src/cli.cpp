// `rayproof render` and `rayproof export-pov`: argument parsing, messages, files.
#include <rayproof/render/cli.hpp>

#include <rayproof/render/image.hpp>
#include <rayproof/render/memory.hpp>
#include <rayproof/render/parse.hpp>
#include <rayproof/render/pov.hpp>
#include <rayproof/render/tracer.hpp>

#include <rayproof/cli.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace rayproof::render {
namespace {

struct Args {
    std::string scene, output;
    std::optional<int> width, height, depth, supersample, threads;
    std::optional<Mode> mode;
    std::vector<Mode> diff;  // --diff A B
    int diff_threshold = 0;
    bool stats = false, quiet = false, progress = false;
    bool no_tree_attenuation = false;
    bool no_prefilter = false;
    bool no_bvh = false;
};

// A mode's name, checked and turned into the enum's value.
const CLI::Validator mode_value(
    [](std::string& s) {
        const std::optional<Mode> m = parse_mode(s);
        if (!m) return "expects fast, conservative or certified, got '" + s + "'";
        s = std::to_string(int(*m));
        return std::string();
    },
    "MODE");
const CLI::Validator image_check(
    [](const std::string& s) {
        return has_image_extension(s) ? "" : "cannot tell the image format of '" + s + "': use .png or .ppm";
    },
    "OUT.png|OUT.ppm");

// The options `render` and `export-pov` share: the scene, the output, the size.
void add_common(CLI::App& cmd, Args& a, const char* output_help) {
    cmd.add_option("SCENE", a.scene, "the scene file (schema: render/scenes/README.md)")->required()->type_name("FILE");
    cmd.add_option("-o,--output", a.output, output_help);
    cmd.add_option("--width", a.width, "image width in pixels")->check(CLI::Range(1, 16384));
    cmd.add_option("--height", a.height, "image height in pixels")->check(CLI::Range(1, 16384));
    cmd.add_flag("--no-tree-attenuation", a.no_tree_attenuation,
                 "turn off the ray tree's distance attenuation (the scene's \"tree_attenuation\")");
}

std::optional<Scene> load(const Args& a, const char* cmd, Progress* progress = nullptr) {
    ParseResult r = load_scene(a.scene, progress);
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
    if (a.no_tree_attenuation) s.tree_attenuation.enabled = false;
    if ((long long)s.settings.width * s.settings.height > (1LL << 26)) {
        std::fprintf(stderr, "rayproof %s: %d x %d pixels is too large\n", cmd, s.settings.width, s.settings.height);
        return std::nullopt;
    }
    return s;
}

std::string cannot_write(const std::string& path, int error) {
    return "cannot write '" + path + "': " + std::strerror(error != 0 ? error : EIO);
}

// "" when `path` can be opened for writing, else "cannot write 'PATH': reason". Run before
// rendering, so that a mistyped output path does not cost a render. An existing file (or
// a character device such as /dev/null or /dev/full) is opened without truncating it; a
// new one is created and removed again, so the check leaves nothing behind. A fifo is
// opened without blocking: with no reader waiting, it fails at once (ENXIO).
std::string check_output(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) return cannot_write(path, EISDIR);
        const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
        if (fd < 0) return cannot_write(path, errno);
        ::close(fd);
        return "";
    }
    if (errno != ENOENT) return cannot_write(path, errno);  // e.g. a part of the path is a file
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY, 0666);
    if (fd < 0) {
        // A dangling symbolic link, or a file created since stat: the write will tell.
        if (errno == EEXIST) return "";
        return cannot_write(path, errno);
    }
    ::close(fd);
    ::unlink(path.c_str());
    return "";
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
    if (const std::string e = check_output(a.output); !e.empty()) {
        std::fprintf(stderr, "rayproof render: %s\n", e.c_str());
        return 1;
    }
    // Progress of the load and the render on stderr: when it is a terminal, or asked for.
    Progress progress(a.progress || (!a.quiet && isatty(STDERR_FILENO)));
    std::optional<Scene> scene = load(a, "render", &progress);
    if (!scene) return 1;

    RenderOptions opt;
    opt.threads = a.threads.value_or(0);
    opt.trace.polyhedron_prefilter = !a.no_prefilter;
    opt.trace.bvh = !a.no_bvh;
    opt.reporter = &progress;
    const int threads = opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const int workers = std::min(threads, scene->settings.height);
    if (const std::string no = refusal(render_need(*scene, workers), available_memory(), "render it"); !no.empty()) {
        std::fprintf(stderr, "rayproof render: %s: %s\n", a.scene.c_str(), no.c_str());
        return 1;
    }

    // The scene is rendered in place, its mode set for each render (no copy of its objects).
    auto render_mode = [&](Mode m) {
        scene->settings.mode = m;
        return render(*scene, opt);
    };

    if (!a.diff.empty()) {
        const auto ra = render_mode(a.diff[0]);
        const auto rb = render_mode(a.diff[1]);
        const ImageComparison c = compare(ra.image, rb.image, a.diff_threshold);
        if (const std::string e = write_image(diff_image(ra.image, rb.image, a.diff_threshold), a.output);
            !e.empty()) {
            std::fprintf(stderr, "rayproof render: %s\n", e.c_str());
            return 1;
        }
        const long long total = (long long)ra.image.width * ra.image.height;
        std::printf("%s vs %s: %lld of %lld pixels differ%s (%.3f%%), largest channel difference %d; wrote %s\n",
                    mode_name(a.diff[0]), mode_name(a.diff[1]), c.differing_pixels, total,
                    a.diff_threshold ? (" by more than " + std::to_string(a.diff_threshold)).c_str() : "",
                    100.0 * double(c.differing_pixels) / double(total), c.max_channel_difference, a.output.c_str());
        if (a.stats) {
            print_stats(ra.stats);
            print_stats(rb.stats);
        }
        return 0;
    }

    const Mode mode = scene->settings.mode;
    const auto r = render_mode(mode);
    if (const std::string e = write_image(r.image, a.output); !e.empty()) {
        std::fprintf(stderr, "rayproof render: %s\n", e.c_str());
        return 1;
    }
    if (!a.quiet)
        std::printf("wrote %s (%dx%d, mode %s, depth %d, %d thread%s, %.2f s)\n", a.output.c_str(), r.image.width,
                    r.image.height, mode_name(mode), scene->settings.depth, threads,
                    threads == 1 ? "" : "s", r.seconds);
    if (a.stats) print_stats(r.stats);
    return 0;
}

int run_export(const Args& a) {
    const std::optional<Scene> scene = load(a, "export-pov");
    if (!scene) return 1;
    const PovScene pov = to_pov(*scene, a.scene);
    for (const std::string& line : pov.inexact) std::fprintf(stderr, "rayproof export-pov: not exact: %s\n", line.c_str());
    const std::string& text = pov.text;
    // Both the write and the flush (or close) are checked: on a full disk the data often
    // goes into stdio's buffer and only the flush fails.
    errno = 0;
    if (a.output.empty()) {
        if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0) {
            std::fprintf(stderr, "rayproof export-pov: cannot write to standard output: %s\n",
                         std::strerror(errno != 0 ? errno : EIO));
            return 1;
        }
        return 0;
    }
    std::FILE* f = std::fopen(a.output.c_str(), "wb");
    if (!f) {
        std::fprintf(stderr, "rayproof export-pov: cannot open '%s': %s\n", a.output.c_str(), std::strerror(errno));
        return 1;
    }
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const int error = errno;
    errno = 0;
    if (std::fclose(f) != 0 || !written) {
        std::fprintf(stderr, "rayproof export-pov: %s\n", cannot_write(a.output, written ? errno : error).c_str());
        return 1;
    }
    return 0;
}

// `rayproof compare A B`: how far two images of the same size are apart.
int run_compare(const std::string& a_path, const std::string& b_path) {
    Image a, b;
    for (const auto& [path, img] : {std::pair<const std::string&, Image&>{a_path, a}, {b_path, b}})
        if (const std::string e = read_image(path, img); !e.empty()) {
            std::fprintf(stderr, "rayproof compare: %s\n", e.c_str());
            return 1;
        }
    const ImageComparison c = compare(a, b);
    if (!c.same_size) {
        std::fprintf(stderr, "rayproof compare: the images differ in size: %dx%d and %dx%d\n", a.width, a.height,
                     b.width, b.height);
        return 1;
    }
    std::printf("mean absolute difference %.3f/255 per channel; largest %d/255; %lld of %lld pixels differ; "
                "PSNR %.2f dB\n",
                c.mean_abs_difference, c.max_channel_difference, c.differing_pixels,
                (long long)a.width * a.height, c.psnr);
    return 0;
}

// Runs `run` on the parsed arguments, turning an exception into status 1.
void set_callback(CLI::App& cmd, const std::shared_ptr<Args>& a, int& status, int (*run)(const Args&)) {
    cmd.callback([&cmd, a, &status, run]() {
        try {
            status = run(*a);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", rayproof::cli::full_name(cmd).c_str(), e.what());
            status = 1;
        }
    });
}

}  // namespace

void add_commands(CLI::App& app, int& status) {
    const auto r = std::make_shared<Args>();
    CLI::App& render = *app.add_subcommand("render", "render a scene file into a PNG or PPM image");
    render.footer("Options override the scene's \"render\" settings.");
    add_common(render, *r, "the image to write; .png or .ppm (binary P6) by extension");
    render.get_option("--output")->required()->check(image_check);
    render.add_option("--mode", r->mode, "kernel mode for every ray query: fast, conservative, certified")
        ->transform(mode_value)
        ->type_name("MODE");
    render.add_option("--depth", r->depth, "longest ray path (1: primary and shadow rays only)")->check(CLI::Range(1, 64));
    render.add_option("--supersample", r->supersample, "N x N rays per pixel")->check(CLI::Range(1, 16));
    render.add_option("--threads", r->threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));
    render
        .add_option("--diff", r->diff,
                    "render in modes A and B, write an image that highlights the pixels where they differ, and "
                    "print how many")
        ->expected(2)
        ->transform(mode_value)
        ->type_name("A B");
    render.add_option("--diff-threshold", r->diff_threshold,
                      "with --diff: count a pixel only when a channel differs by more than N (of 255); default 0")
        ->check(CLI::Range(0, 254));
    render.add_flag("--stats", r->stats, "print ray and kernel-query counts");
    render.add_flag("--no-prefilter", r->no_prefilter,
                    "ask every polyhedron's planes, without its bounding-sphere pre-filter (to measure it)");
    render.add_flag("--no-bvh", r->no_bvh,
                    "ask every object for every ray instead of the scene's BVH (the brute force, to compare and measure)");
    render.add_flag("-q,--quiet", r->quiet, "print nothing on success");
    render.add_flag("--progress", r->progress,
                    "show the progress of long loads and renders on stderr even when it is not a terminal");
    set_callback(render, r, status, run_render);

    const auto e = std::make_shared<Args>();
    CLI::App& pov = *app.add_subcommand("export-pov", "print a scene file as a POV-Ray 3.7 scene");
    pov.footer("e.g. rayproof export-pov scene.json > scene.pov && povray +W320 +H240 scene.pov");
    add_common(pov, *e, "write into this file instead of stdout");
    set_callback(pov, e, status, run_export);

    const auto images = std::make_shared<std::vector<std::string>>();
    CLI::App& cmp = *app.add_subcommand("compare", "how far two images (PNG or PPM, same size) are apart");
    cmp.add_option("IMAGES", *images, "the two images")->required()->expected(2)->type_name("A B");
    cmp.callback([images, &status] { status = run_compare((*images)[0], (*images)[1]); });
}

}  // namespace rayproof::render
