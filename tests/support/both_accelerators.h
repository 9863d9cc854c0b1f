// Tests that hold for every accelerator are written once and run for each:
// TEST_P(Suite, Name) with GetParam() the accelerator's name ("naive",
// "embree"), then PENUMBRA_FOR_BOTH_ACCELERATORS(Suite). Results are named
// BothAccelerators/Suite.Name/naive and .../embree.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace penumbra::test {

class ForBothAccelerators : public ::testing::TestWithParam<std::string> {};

inline std::string acceleratorName(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

}  // namespace penumbra::test

#define PENUMBRA_FOR_BOTH_ACCELERATORS(Suite)                                                                 \
    INSTANTIATE_TEST_SUITE_P(BothAccelerators, Suite, ::testing::Values(std::string("naive"), std::string("embree")), \
                             ::penumbra::test::acceleratorName)
