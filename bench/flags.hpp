// bench/flags.hpp — the benchmark programs' own flags, --NAME=VALUE, read from what is
// left of argv once benchmark::Initialize has taken Google Benchmark's flags
// (rayproof_bench and rayproof_bench_counters).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <initializer_list>

namespace rayproof::bench {

struct Flag {
    const char* name;                       // "--cases"
    std::function<void(const char*)> set;   // reads the text after '='
};

// A count: decimal.
inline Flag count_flag(const char* name, std::size_t& v) {
    return {name, [&v](const char* s) { v = std::strtoull(s, nullptr, 10); }};
}
// A seed: decimal, or hexadecimal with 0x, or octal with 0.
inline Flag seed_flag(const char* name, std::uint64_t& v) {
    return {name, [&v](const char* s) { v = std::strtoull(s, nullptr, 0); }};
}
// A duration in seconds.
inline Flag seconds_flag(const char* name, double& v) {
    return {name, [&v](const char* s) { v = std::strtod(s, nullptr); }};
}

// Sets every flag given as NAME=VALUE in argv and removes it; the other arguments stay,
// in their order, for benchmark::ReportUnrecognizedArguments.
inline void take_flags(int& argc, char** argv, std::initializer_list<Flag> flags) {
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const Flag* match = nullptr;
        for (const Flag& f : flags) {
            const std::size_t n = std::strlen(f.name);
            if (std::strncmp(a, f.name, n) == 0 && a[n] == '=') match = &f;
        }
        if (match)
            match->set(a + std::strlen(match->name) + 1);
        else
            argv[kept++] = argv[i];
    }
    argc = kept;
}

// "usage: PROGRAM [benchmark flags] FLAGS" on stderr; the exit status of a usage error.
inline int usage_error(const char* program, const char* flags) {
    std::fprintf(stderr, "usage: %s [benchmark flags] %s", program, flags);
    return 2;
}

}  // namespace rayproof::bench
