// rayproof/render/progress.hpp — progress of long loads and renders, on a stream (stderr).
//
// Nothing is written for the first second: short runs stay silent. After that a reporter
// thread redraws one line every 100 ms, "\r<what> [####......]  42%   3.1s" when the phase
// has a known total, "\r<what> ...   3.1s" otherwise; a phase that drew anything ends its
// line with '\n' when the next phase starts or the Progress is destroyed. Counting is an
// atomic store or add, so the workers that count pay next to nothing, and a disabled
// Progress (the default: the command line enables it when stderr is a terminal or with
// --progress, never for the image files) starts no thread and writes nothing.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace rayproof::render {

class Progress {
public:
    Progress() = default;                                   // disabled
    explicit Progress(bool enabled, std::FILE* out = stderr);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    bool enabled() const { return enabled_; }
    // A new phase: its name and its total (0: unknown, no bar). The clock keeps running
    // from the construction: the one-second grace is for the whole run, not per phase.
    void phase(std::string what, std::uint64_t total = 0);
    void set(std::uint64_t done) { done_.store(done, std::memory_order_relaxed); }
    void add(std::uint64_t n) { done_.fetch_add(n, std::memory_order_relaxed); }
    // Ends the current phase's line (if one was drawn); the next phase() starts another.
    void finish();

private:
    void run();
    void draw(bool final);  // with mu_ held

    bool enabled_ = false;
    std::FILE* out_ = nullptr;
    std::chrono::steady_clock::time_point t0_{};
    std::atomic<std::uint64_t> done_{0};
    std::mutex mu_;
    std::condition_variable cv_;
    std::string what_;
    std::uint64_t total_ = 0;
    bool drawn_ = false;  // the current phase's line has been drawn
    bool stop_ = false;
    std::thread reporter_;
};

}  // namespace rayproof::render
