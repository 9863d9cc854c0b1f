// A Logger that keeps the warnings it is given, for tests that assert on them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/log.h"

namespace penumbra::test {

struct WarningLog {
    std::vector<std::string> warnings;
    Logger logger{[this](LogLevel level, std::string_view msg) {
                      if (level == LogLevel::Warning) warnings.emplace_back(msg);
                  },
                  LogLevel::Debug};

    WarningLog() = default;
    WarningLog(const WarningLog&) = delete;
    WarningLog& operator=(const WarningLog&) = delete;
};

}  // namespace penumbra::test
