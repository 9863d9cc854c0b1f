// Render progress on stderr: a bar with ETA on a terminal, plain periodic
// lines otherwise (logs, CI), nothing when quiet.
#pragma once

#include <chrono>
#include <cstddef>

namespace penumbra::cli {

class ProgressReporter {
public:
    explicit ProgressReporter(bool quiet);
    /// Called with tiles done / total (never concurrently).
    void update(size_t done, size_t total);
    /// Ends the bar line.
    void finish();

private:
    bool quiet_;
    bool tty_;
    std::chrono::steady_clock::time_point start_, lastPrint_;
    int lastPercent_ = -1;
};

}  // namespace penumbra::cli
