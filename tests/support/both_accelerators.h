// Tests that hold for every accelerator are written once and run for each:
// TEST_P(Suite, Name) with GetParam() the accelerator (pnb::AcceleratorKind),
// then PENUMBRA_FOR_BOTH_ACCELERATORS(Suite). Results are named
// BothAccelerators/Suite.Name/naive and .../embree.
#pragma once

#include <gtest/gtest.h>

#include <ostream>
#include <penumbra/types.hpp>
#include <string>

namespace pnb {
/// The accelerator's name in test output (found by argument-dependent lookup).
inline void PrintTo(AcceleratorKind kind, std::ostream* os) {
    *os << (kind == AcceleratorKind::Naive ? "naive" : "embree");
}
}  // namespace pnb

namespace penumbra::test {

class ForBothAccelerators : public ::testing::TestWithParam<pnb::AcceleratorKind> {};

inline std::string acceleratorName(const ::testing::TestParamInfo<pnb::AcceleratorKind>& info) {
    return info.param == pnb::AcceleratorKind::Naive ? "naive" : "embree";
}

}  // namespace penumbra::test

#define PENUMBRA_FOR_BOTH_ACCELERATORS(Suite)                                                                     \
    INSTANTIATE_TEST_SUITE_P(BothAccelerators, Suite,                                                             \
                             ::testing::Values(pnb::AcceleratorKind::Naive, pnb::AcceleratorKind::Embree),        \
                             ::penumbra::test::acceleratorName)
