// bench/watchdog.hpp — runs a piece of work in a child process with a deadline, so that
// a method that hangs or crashes on some case is reported (with the case it was on)
// instead of stopping a whole benchmark or accuracy run. POSIX (fork, waitpid).
//
//   Watchdog w;                    // shared progress and result words
//   std::string why;
//   bool ok = w.run(seconds, [&](Watchdog::Shared& s) { for (i...) { s.progress = i; ... } }, why);
//
// The child sees the parent's memory copy-on-write; it reports back through the shared
// words only (progress, and up to four numbers in `value`).
#pragma once

#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rayproof::bench {

class Watchdog {
public:
    struct Shared {
        volatile unsigned long long progress;
        volatile unsigned long long value[4];
    };

    Watchdog() {
        void* p = mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) {
            std::perror("mmap");
            std::exit(1);
        }
        shared_ = static_cast<Shared*>(p);
    }
    ~Watchdog() { munmap(shared_, sizeof(Shared)); }
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;

    const Shared& shared() const { return *shared_; }

    // Runs work(shared) in a child; true when it returned within `seconds`. Otherwise
    // `why` says what happened and at which progress value ("timeout at case 12").
    template <class Work> bool run(double seconds, Work&& work, std::string& why) {
        shared_->progress = 0;
        for (auto& v : shared_->value) v = 0;
        std::fflush(stdout);
        std::fflush(stderr);
        const pid_t pid = fork();
        if (pid < 0) {
            std::perror("fork");
            std::exit(1);
        }
        if (pid == 0) {
            work(*shared_);
            std::fflush(stdout);
            std::fflush(stderr);
            _exit(0);
        }
        const auto start = std::chrono::steady_clock::now();
        int status = 0;
        bool timed_out = false;
        for (useconds_t nap = 100;; nap = std::min<useconds_t>(nap * 2, 20000)) {
            if (waitpid(pid, &status, WNOHANG) == pid) break;
            if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
                kill(pid, SIGKILL);
                waitpid(pid, &status, 0);
                timed_out = true;
                break;
            }
            usleep(nap);
        }
        const std::string at = " at case " + std::to_string(shared_->progress);
        if (timed_out)
            why = "timeout" + at;
        else if (WIFSIGNALED(status))
            why = "signal " + std::to_string(WTERMSIG(status)) + at;
        else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
            why = "exit " + std::to_string(WEXITSTATUS(status)) + at;
        else
            return true;
        return false;
    }

private:
    Shared* shared_;
};

}  // namespace rayproof::bench
