// What a scene needs in memory and what the machine has (memory.hpp).
#include <rayproof/render/memory.hpp>
#include <rayproof/render/tracer.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <limits>

namespace rayproof::render {

namespace {

constexpr std::uint64_t none = std::numeric_limits<std::uint64_t>::max();

std::uint64_t sat_add(std::uint64_t a, std::uint64_t b) { return a > none - b ? none : a + b; }
std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b) { return b != 0 && a > none / b ? none : a * b; }

// The tokens of a JSON text, counted outside strings ('{', '[', ',', ':') and as strings.
struct Tokens {
    std::uint64_t objects = 0, arrays = 0, commas = 0, colons = 0;
    std::uint64_t strings = 0, string_bytes = 0;
    std::uint64_t polyhedra = 0;  // the string "polyhedron": at most one per polyhedron object
};

Tokens count_tokens(std::string_view t) {
    Tokens k;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const char c = t[i];
        if (c == '"') {
            const std::size_t begin = ++i;
            while (i < t.size() && t[i] != '"') i += t[i] == '\\' ? 2 : 1;
            const std::size_t len = std::min(i, t.size()) - begin;
            ++k.strings;
            k.string_bytes += len;
            if (t.substr(begin, len) == "polyhedron") ++k.polyhedra;
        } else if (c == '{') {
            ++k.objects;
        } else if (c == '[') {
            ++k.arrays;
        } else if (c == ',') {
            ++k.commas;
        } else if (c == ':') {
            ++k.colons;
        }
    }
    return k;
}

// A positive number from /proc-style "Key:   123 kB" lines, in bytes; none if absent.
std::uint64_t meminfo_kb(const char* key) {
    std::ifstream f("/proc/meminfo");
    std::string name;
    std::uint64_t value = 0;
    std::string unit;
    while (f >> name >> value) {
        std::getline(f, unit);
        if (name == key) return sat_mul(value, 1024);
    }
    return none;
}

// The first number of a file (cgroup's memory.max is "max" when unlimited: none).
std::uint64_t file_number(const char* path) {
    std::ifstream f(path);
    std::string s;
    if (!(f >> s) || s.empty() || s[0] < '0' || s[0] > '9') return none;
    return std::strtoull(s.c_str(), nullptr, 10);
}

}  // namespace

std::uint64_t MemoryNeed::total() const {
    std::uint64_t t = 0;
    for (const Part& p : parts) t = sat_add(t, p.bytes);
    return t;
}

std::string format_bytes(std::uint64_t b) {
    char buf[64];
    if (b == none) return "unbounded";
    if (b < 1000) std::snprintf(buf, sizeof buf, "%" PRIu64 " B", b);
    else if (b < 1'000'000) std::snprintf(buf, sizeof buf, "%.1f kB", double(b) / 1e3);
    else if (b < 1'000'000'000) std::snprintf(buf, sizeof buf, "%.1f MB", double(b) / 1e6);
    else std::snprintf(buf, sizeof buf, "%.2f GB", double(b) / 1e9);
    return buf;
}

std::string MemoryNeed::describe() const {
    std::string s = format_bytes(total()) + " (";
    for (std::size_t i = 0; i < parts.size(); ++i)
        s += (i ? ", " : "") + std::string(parts[i].what) + " " + format_bytes(parts[i].bytes);
    return s + ")";
}

// The bounds, per token, with glibc's chunk of n asked bytes taking at most
// max(32, n + 24) (n + 8 rounded up to 16) and libstdc++'s sizes on a 64-bit target:
//   a JSON value is a 16-byte basic_json in its parent; an array's values sit in a vector
//     that grows by doubling, so at most 32 bytes per value, plus the vector itself on the
//     heap (24 -> 32) and its buffer's chunk overhead (24): 80 per '[' and 32 per ','
//     (values <= commas + arrays);
//   an object is a std::map on the heap (48 -> 64); each member a tree node of 32 + a
//     32-byte key string + the 16-byte value, 80 -> 96 per ':';
//   a string value is a std::string on the heap (32 -> 48), and every string longer than
//     15 bytes (keys too) its characters in a chunk of at most length + 1 + 24: 80 per
//     string and 2 per string byte covers them all;
//   the Scene: each '{' may be one Object, Material, Light or plane (sizeof each, the
//     vectors of materials, lights and planes doubling: twice theirs), names are strings
//     (their bytes counted again), and a polyhedron given by points or a preset holds its
//     hull: at most 2·64 - 4 planes and 64 points, 8 kB with its vectors.
MemoryNeed scene_text_need(std::string_view text) {
    const Tokens k = count_tokens(text);
    std::uint64_t tree = 0;
    tree = sat_add(tree, sat_mul(k.objects, 64));
    tree = sat_add(tree, sat_mul(k.colons, 96));
    tree = sat_add(tree, sat_mul(k.arrays, 80));
    tree = sat_add(tree, sat_mul(k.commas, 32));
    tree = sat_add(tree, sat_mul(k.strings, 80));
    tree = sat_add(tree, sat_mul(k.string_bytes, 2));
    const std::uint64_t per_brace =
        sizeof(Object) + 2 * sizeof(Material) + 2 * sizeof(Light) + 2 * sizeof(Plane<double>) + 64;
    std::uint64_t scene = sat_mul(k.objects, per_brace);
    scene = sat_add(scene, sat_add(k.string_bytes, sat_mul(k.strings, 24)));
    scene = sat_add(scene, sat_mul(k.polyhedra, 8192));
    MemoryNeed n;
    n.parts.push_back({"scene text", text.size()});
    n.parts.push_back({"JSON tree", tree});
    n.parts.push_back({"scene", scene});
    return n;
}

// The BVH (tracer.cpp builds one Bvh<double, scene_bvh_width> over the objects and the
// visible lights' spheres): while it is built, the tracer's list of primitives and the
// Bvh's copy of it, the build's scratch (a box, a centroid and an index per primitive, 80
// bytes), the index arrays (4 and 8 bytes per primitive at most), and its nodes. A node
// covers more than leaf_size = 1 primitive and has at least two lanes, so there are fewer
// nodes than primitives; the tree the binned SAH builds has far fewer (one node per about
// 5 primitives measured on 100,000 generated balls with W = 8, per 2.5 with W = 4), and
// the estimate takes one per 2 primitives, three times over for the vector's growth (up
// to twice its size) and its final shrink (one more copy). The copies are then put in
// leaf order in place, with one bit per primitive, after the scratch is freed, and the
// balls among them copied once more compactly (32 bytes each, fewer than the scratch's
// 80 just freed, so the peak is the build's).
std::uint64_t bvh_need(std::uint64_t primitives) {
    const std::uint64_t per_primitive = 2 * sizeof(Primitive<double>) + 9 * sizeof(double) + 8 + 4 + 8;
    const std::uint64_t nodes = primitives / 2 + 1;
    const std::uint64_t node_bytes = sizeof(detail::BvhNode<double, scene_bvh_width>);
    return sat_add(sat_mul(primitives, per_primitive), sat_mul(sat_mul(nodes, 3), node_bytes));
}

MemoryNeed render_need(const Scene& scene, int threads) {
    MemoryNeed n;
    const auto& st = scene.settings;
    std::uint64_t prims = scene.objects.size();
    for (const Light& l : scene.lights) prims += l.visible();
    n.parts.push_back({"BVH", bvh_need(prims)});
    n.parts.push_back({"image", sat_mul(sat_mul(std::uint64_t(std::max(st.width, 0)), std::uint64_t(std::max(st.height, 0))), 3)});
    // Each worker thread's stack (glibc reserves RLIMIT_STACK's soft limit, 8 MB unless
    // changed; 8 MB taken when it is unlimited) and the progress reporter's.
    std::uint64_t stack = 8u << 20;
    rlimit rl{};
    if (::getrlimit(RLIMIT_STACK, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) stack = rl.rlim_cur;
    n.parts.push_back({"thread stacks", sat_mul(stack, std::uint64_t(std::max(threads, 0)) + 1)});
    return n;
}

MemoryAvailable available_memory() {
    MemoryAvailable a;
    a.bytes = none;
    std::string how;
    const auto note = [&](const std::string& s) { how += (how.empty() ? "" : "; ") + s; };

    std::uint64_t phys = meminfo_kb("MemAvailable:");
    if (phys != none) {
        note("MemAvailable " + format_bytes(phys));
    } else {
        const long pages = ::sysconf(_SC_AVPHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
        if (pages > 0 && size > 0) {
            phys = sat_mul(std::uint64_t(pages), std::uint64_t(size));
            note("available physical memory " + format_bytes(phys));
        }
    }
    a.bytes = std::min(a.bytes, phys);

    rlimit rl{};
    if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
        std::uint64_t used = 0;
        std::ifstream statm("/proc/self/statm");
        std::uint64_t pages = 0;
        const long size = ::sysconf(_SC_PAGESIZE);
        if (statm >> pages && size > 0) used = sat_mul(pages, std::uint64_t(size));
        const std::uint64_t limit = rl.rlim_cur;
        const std::uint64_t left = limit > used ? limit - used : 0;
        note("RLIMIT_AS " + format_bytes(limit) + ", " + format_bytes(used) + " of it in use");
        a.bytes = std::min(a.bytes, left);
    }

    const std::uint64_t max = file_number("/sys/fs/cgroup/memory.max");
    if (max != none) {
        const std::uint64_t cur = file_number("/sys/fs/cgroup/memory.current");
        const std::uint64_t used = cur == none ? 0 : cur;
        note("cgroup memory.max " + format_bytes(max) + ", " + format_bytes(used) + " of it in use");
        a.bytes = std::min(a.bytes, max > used ? max - used : 0);
    }
    a.how = how.empty() ? "no limit found" : how;
    return a;
}

std::string refusal(const MemoryNeed& need, const MemoryAvailable& avail, const char* doing) {
    if (need.total() <= avail.bytes) return "";
    return "needs about " + need.describe() + " to " + doing + ", but only " + format_bytes(avail.bytes) +
           " are available (" + avail.how + ")";
}

}  // namespace rayproof::render
