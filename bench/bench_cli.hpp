// bench/bench_cli.hpp — the command line of the Google Benchmark programs: Google
// Benchmark takes its own --benchmark_* flags first (benchmark::Initialize; its --help
// lists them after the program's options), then CLI11 reads the program's options from
// what is left (rayproof/cli.hpp: unknown options and bad values are usage errors).
#pragma once

#include <rayproof/cli.hpp>

#include <benchmark/benchmark.h>

#include <iostream>
#include <optional>

namespace rayproof::bench {

// Parses argv into app: nothing when the program is to go on, else its exit status.
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
    static const CLI::App* shown = nullptr;
    shown = &app;
    app.footer("Google Benchmark's own flags (--benchmark_filter=REGEX, --benchmark_format=json, ...) come first; "
               "--help lists them.");
    benchmark::Initialize(&argc, argv, [] {
        std::cout << shown->help() << "\nGoogle Benchmark's flags:\n";
        benchmark::PrintDefaultHelp();
    });
    return cli::parse(app, argc, argv);
}

}  // namespace rayproof::bench
