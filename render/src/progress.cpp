// Progress lines on stderr for long loads and renders (progress.hpp).
#include <rayproof/render/progress.hpp>

#include <algorithm>

namespace rayproof::render {

Progress::Progress(bool enabled, std::FILE* out)
    : enabled_(enabled && out != nullptr), out_(out), t0_(std::chrono::steady_clock::now()) {
    if (enabled_) reporter_ = std::thread([this] { run(); });
}

Progress::~Progress() {
    if (!enabled_) return;
    {
        const std::lock_guard<std::mutex> lock(mu_);
        stop_ = true;
        if (drawn_) draw(true);
    }
    cv_.notify_all();
    reporter_.join();
}

void Progress::phase(std::string what, std::uint64_t total) {
    if (!enabled_) return;
    const std::lock_guard<std::mutex> lock(mu_);
    if (drawn_) draw(true);
    drawn_ = false;
    what_ = std::move(what);
    total_ = total;
    done_.store(0, std::memory_order_relaxed);
}

void Progress::finish() {
    if (!enabled_) return;
    const std::lock_guard<std::mutex> lock(mu_);
    if (drawn_) draw(true);
    drawn_ = false;
    what_.clear();
}

void Progress::run() {
    std::unique_lock<std::mutex> lock(mu_);
    while (!stop_) {
        cv_.wait_for(lock, std::chrono::milliseconds(100));
        if (stop_) break;
        if (what_.empty()) continue;
        if (std::chrono::steady_clock::now() - t0_ < std::chrono::seconds(1)) continue;
        draw(false);
    }
}

void Progress::draw(bool final) {
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    if (total_ > 0) {
        const std::uint64_t done = std::min(done_.load(std::memory_order_relaxed), total_);
        const int filled = int(done * 40 / total_);
        const std::string bar = std::string(std::size_t(filled), '#') + std::string(std::size_t(40 - filled), '.');
        std::fprintf(out_, "\r%s [%s] %3d%% %6.1fs", what_.c_str(), bar.c_str(), int(done * 100 / total_), sec);
    } else {
        std::fprintf(out_, "\r%s ... %6.1fs", what_.c_str(), sec);
    }
    if (final) std::fputc('\n', out_);
    std::fflush(out_);
    drawn_ = true;
}

}  // namespace rayproof::render
