// rayproof/render/memory.hpp — what a scene needs in memory, what the machine has, and
// the refusal of a scene that cannot fit, before the memory is allocated (a clear
// message and a nonzero exit instead of an out-of-memory kill or a bad_alloc midway).
//
// Need, in two steps:
//   parsing (scene_text_need, before nlohmann-json reads a byte): the text, the JSON
//     document tree and the Scene, each bounded from a count of the text's tokens (see
//     memory.cpp for the per-token sizes: libstdc++'s containers on glibc's malloc, whose
//     chunks take max(32, round_up(n + 8, 16)) bytes for n asked);
//   rendering (render_need, once the Scene is read and the document freed): the BVH (its
//     build's peak: two lists of primitives, the scratch, and an estimate of the nodes,
//     see memory.cpp), the image and the worker threads' stacks.
// Available (available_memory): the least of
//   MemAvailable of /proc/meminfo (or sysconf _SC_AVPHYS_PAGES · _SC_PAGESIZE),
//   RLIMIT_AS less the address space already in use (/proc/self/statm), when set,
//   the cgroup's memory.max less its memory.current (cgroup v2), when set.
// Each is a snapshot (other processes may take memory meanwhile): the check turns away
// what cannot fit, it cannot promise that what fits will still fit later.
#pragma once

#include <rayproof/render/scene.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rayproof::render {

struct MemoryNeed {
    struct Part {
        const char* what;
        std::uint64_t bytes;
    };
    std::vector<Part> parts;
    std::uint64_t total() const;
    std::string describe() const;  // "1.2 GB (scene text 15 MB, JSON tree 160 MB, ...)"
};

struct MemoryAvailable {
    std::uint64_t bytes = 0;  // the least of the limits below
    std::string how;          // each limit found, e.g. "MemAvailable 3.1 GB; RLIMIT_AS 512 MB, 90 MB of it in use"
};

// Upper bounds for parsing `text` (see above).
MemoryNeed scene_text_need(std::string_view text);
// What rendering `scene` with `threads` worker threads takes beyond the Scene.
MemoryNeed render_need(const Scene& scene, int threads);
MemoryAvailable available_memory();

// "" when need fits in avail; otherwise the refusal, naming both:
// "needs about 1.2 GB to <doing> (...), but only 800 MB are available (...)".
std::string refusal(const MemoryNeed& need, const MemoryAvailable& avail, const char* doing);

// Bytes as "950 B", "15.1 MB", "1.20 GB" (decimal units).
std::string format_bytes(std::uint64_t bytes);

}  // namespace rayproof::render
