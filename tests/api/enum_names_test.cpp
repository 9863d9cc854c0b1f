// The one name table of the settings' enums (penumbra/names.hpp): every value
// has exactly one written name, every name reads back as its value, and the
// lists the messages print are the ones the command line and JSON used to spell.
#include <gtest/gtest.h>

#include <penumbra/names.hpp>
#include <set>
#include <string>

namespace {

template <class E>
void expectRoundTrip() {
    std::set<std::string_view> seen;
    for (const auto& entry : pnb::EnumNames<E>::table) {
        EXPECT_TRUE(seen.insert(entry.name).second) << "a name twice: " << entry.name;
        ASSERT_TRUE(pnb::enumFromName<E>(entry.name).has_value()) << entry.name;
        EXPECT_EQ(*pnb::enumFromName<E>(entry.name), entry.value) << entry.name;
        // Every value's written name is a listed one that reads back as that value.
        const std::string_view written = pnb::enumName(entry.value);
        EXPECT_FALSE(written.empty()) << entry.name;
        EXPECT_EQ(*pnb::enumFromName<E>(written), entry.value) << entry.name;
    }
    EXPECT_FALSE(pnb::enumFromName<E>("").has_value());
    EXPECT_FALSE(pnb::enumFromName<E>("no such name").has_value());
}

TEST(EnumNames, EveryNameReadsBackAsItsValue) {
    expectRoundTrip<pnb::IntegratorKind>();
    expectRoundTrip<pnb::LightSelection>();
    expectRoundTrip<pnb::DirectLightSampling>();
    expectRoundTrip<pnb::AcceleratorKind>();
    expectRoundTrip<pnb::BuildQuality>();
    expectRoundTrip<pnb::PhongModel>();
}

TEST(EnumNames, ListsForMessages) {
    EXPECT_EQ(pnb::enumNameList<pnb::LightSelection>(), "auto, all, power or tree");
    EXPECT_EQ(pnb::enumNameList<pnb::IntegratorKind>("\""), "\"whitted\" or \"path\"");
    EXPECT_EQ(pnb::enumNameList<pnb::DirectLightSampling>("'"), "'mis' or 'light'");
    // The British spelling is read, never listed or written.
    EXPECT_EQ(pnb::enumNameList<pnb::PhongModel>(), "classic or normalized");
    EXPECT_EQ(*pnb::enumFromName<pnb::PhongModel>("normalised"), pnb::PhongModel::Normalized);
    EXPECT_EQ(pnb::enumName(pnb::PhongModel::Normalized), "normalized");
}

TEST(EnumNames, ValuesOutsideTheEnumHaveNoName) {
    EXPECT_EQ(pnb::enumName(static_cast<pnb::LightSelection>(99)), "");
}

}  // namespace
