// Logging through a sink the owner sets. No global logger: every loader and the
// renderer receive the Logger they should report to.
#pragma once

#include <penumbra/types.hpp>

#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace penumbra {

using LogLevel = pnb::LogLevel;  // api/include/penumbra/types.hpp

class Logger {
public:
    using Sink = std::function<void(LogLevel, std::string_view)>;

    /// Default: warnings and errors to stderr.
    Logger() = default;
    explicit Logger(Sink sink, LogLevel minLevel = LogLevel::Info) : sink_(std::move(sink)), min_(minLevel) {}

    void setSink(Sink sink) { sink_ = std::move(sink); }
    void setMinLevel(LogLevel l) { min_ = l; }

    void log(LogLevel level, std::string_view msg) const {
        if (level < min_) return;
        if (sink_) {
            sink_(level, msg);
            return;
        }
        static constexpr const char* kNames[] = {"debug", "info", "warning", "error"};
        std::fprintf(stderr, "penumbra: %s: %.*s\n", kNames[static_cast<int>(level)], static_cast<int>(msg.size()),
                     msg.data());
    }
    void debug(std::string_view m) const { log(LogLevel::Debug, m); }
    void info(std::string_view m) const { log(LogLevel::Info, m); }
    void warn(std::string_view m) const { log(LogLevel::Warning, m); }
    void error(std::string_view m) const { log(LogLevel::Error, m); }

private:
    Sink sink_;
    LogLevel min_ = LogLevel::Warning;
};

}  // namespace penumbra
