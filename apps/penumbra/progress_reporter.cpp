#include "progress_reporter.h"

#include <unistd.h>

#include <cstdio>

namespace penumbra::cli {

ProgressReporter::ProgressReporter(bool quiet)
    : quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()), lastPrint_(start_) {}

void ProgressReporter::update(size_t done, size_t total) {
    if (quiet_ || total == 0) return;
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fraction = double(done) / double(total);
    const int percent = int(fraction * 100.0);
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (tty_) {
        if (percent == lastPercent_ && done != total) return;
        constexpr int kWidth = 40;
        int filled = int(fraction * kWidth);
        char bar[kWidth + 1];
        for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '-';
        bar[kWidth] = '\0';
        std::fprintf(stderr, "\r[%s] %3d%%  %.1fs elapsed, ETA %.1fs ", bar, percent, elapsed, eta);
        std::fflush(stderr);
    } else {
        // Plain lines at most every 2 seconds or 10%, plus the last one.
        const double sinceLast = std::chrono::duration<double>(now - lastPrint_).count();
        if (done != total && sinceLast < 2.0 && percent / 10 == lastPercent_ / 10) return;
        std::fprintf(stderr, "penumbra: %d%% (%zu/%zu tiles), %.1fs elapsed, ETA %.1fs\n", percent, done, total, elapsed,
                     eta);
        lastPrint_ = now;
    }
    lastPercent_ = percent;
}

void ProgressReporter::finish() {
    if (!quiet_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace penumbra::cli
