// replay_main.cpp — a main() for the fuzz targets without a fuzzing engine: runs
// LLVMFuzzerTestOneInput once on each file named on the command line, or on every file
// of each directory named (recursively, in sorted order, skipping names that start
// with '.'), so that any compiler (g++ included) replays the corpora and the
// regressions. A failing input aborts the program after printing the case (the
// harness names the file being replayed); the exit status is 0 when all inputs pass,
// 2 on a usage error. `-v` prints each file name before running it. The triage filters
// (RAYPROOF_FUZZ_ONLY, RAYPROOF_FUZZ_IGNORE) are ignored: every input is judged in full.
#include "fuzz_common.hpp"

#include <rayproof/cli.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace fs = std::filesystem;

namespace {

bool hidden(const fs::path& p) {
    const std::string name = p.filename().string();
    return !name.empty() && name[0] == '.';
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Runs the fuzz target once on each file given, and on every file under each directory given.",
                 fs::path(argv[0]).filename().string()};
    bool verbose = false;
    std::vector<std::string> args;
    app.add_flag("-v", verbose, "print each file name before running it");
    app.add_option("FILE_OR_DIR", args, "the inputs")->required();
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    rayproof::fuzz::filters_enabled() = false;
    for (const char* var : {"RAYPROOF_FUZZ_ONLY", "RAYPROOF_FUZZ_IGNORE"})
        if (const char* v = std::getenv(var); v && *v) std::cerr << argv[0] << ": " << var << " is ignored by the replay\n";
    std::vector<fs::path> files;
    for (const std::string& arg : args) {
        std::error_code ec;
        if (fs::is_directory(arg, ec)) {
            std::vector<fs::path> found;
            for (auto it = fs::recursive_directory_iterator(arg, ec); !ec && it != fs::recursive_directory_iterator();
                 it.increment(ec)) {
                if (hidden(it->path())) {
                    if (it->is_directory()) it.disable_recursion_pending();
                    continue;
                }
                if (it->is_regular_file()) found.push_back(it->path());
            }
            std::sort(found.begin(), found.end());
            files.insert(files.end(), found.begin(), found.end());
        } else if (fs::is_regular_file(arg, ec)) {
            files.emplace_back(arg);
        } else {
            std::cerr << argv[0] << ": no such file or directory: " << arg << '\n';
            return rayproof::cli::usage_error;
        }
    }
    std::size_t bytes = 0;
    for (const fs::path& f : files) {
        std::ifstream in(f, std::ios::binary);
        const std::vector<char> data{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        if (!in.good() && !in.eof()) {
            std::cerr << argv[0] << ": cannot read " << f << '\n';
            return 2;
        }
        rayproof::fuzz::current_input() = f.string();
        if (verbose) std::cout << f.string() << std::endl;
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
        bytes += data.size();
    }
    std::cout << "replayed " << files.size() << " inputs (" << bytes << " bytes): all passed\n";
    return 0;
}
