// fuzz_common.hpp — what every fuzz target shares: the name of the input being replayed
// (set by the replay program, replay_main.cpp, so that a failing check names the file;
// empty under a fuzzing engine, which names its own crash files) and the triage filters.
#pragma once

#include <cstdlib>
#include <string>

namespace rayproof::fuzz {

inline std::string& current_input() {
    static std::string name;
    return name;
}

// Triage aids for campaigns and minimization (never set in CI): a violation whose
// description contains a ';'-separated substring of RAYPROOF_FUZZ_IGNORE, or none of
// RAYPROOF_FUZZ_ONLY, does not abort (the input counts as passing). A description reads
// "<what> (mode <mode>, <float|double>, <shape>)" for the shape targets, "<what>" for
// scene_fuzz.
// The replay (replay_main.cpp) switches them off: a replayed input is judged unfiltered,
// whatever the environment holds, so a failing regression cannot pass because a filter
// was left set.
struct Filtered {};
inline bool& filters_enabled() {
    static bool on = true;
    return on;
}
inline bool listed(const char* var, const std::string& what) {
    const char* v = std::getenv(var);
    if (!v || !*v) return false;
    const std::string list = v;
    for (std::size_t b = 0; b <= list.size();) {
        std::size_t e = list.find(';', b);
        if (e == std::string::npos) e = list.size();
        if (e > b && what.find(list.substr(b, e - b)) != std::string::npos) return true;
        b = e + 1;
    }
    return false;
}
inline void filter(const std::string& what) {
    if (!filters_enabled()) return;
    const char* only = std::getenv("RAYPROOF_FUZZ_ONLY");
    if (listed("RAYPROOF_FUZZ_IGNORE", what) || (only && *only && !listed("RAYPROOF_FUZZ_ONLY", what))) throw Filtered{};
}

}  // namespace rayproof::fuzz
