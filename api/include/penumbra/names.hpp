// The one spelling of each setting's enum values: the names the command line,
// JSON scene files, the Python module and --stats-json all use, so that a
// value added to an enum is named once. C++17, like penumbra.hpp.
#pragma once

#include <iterator>
#include <optional>
#include <string>
#include <string_view>

#include <penumbra/types.hpp>

namespace pnb {

template <class E>
struct EnumName {
    std::string_view name;
    E value;
    bool listed = true;  ///< false for another spelling accepted on input, never written or listed
};

/// EnumNames<E>::table lists every value of E with its name, in the order
/// messages list them.
template <class E>
struct EnumNames;

template <>
struct EnumNames<IntegratorKind> {
    static constexpr EnumName<IntegratorKind> table[] = {{"whitted", IntegratorKind::Whitted},
                                                          {"path", IntegratorKind::Path}};
};

template <>
struct EnumNames<LightSelection> {
    static constexpr EnumName<LightSelection> table[] = {{"auto", LightSelection::Auto},
                                                          {"all", LightSelection::All},
                                                          {"power", LightSelection::Power},
                                                          {"tree", LightSelection::Tree}};
};

template <>
struct EnumNames<DirectLightSampling> {
    static constexpr EnumName<DirectLightSampling> table[] = {{"mis", DirectLightSampling::Mis},
                                                               {"light", DirectLightSampling::Light}};
};

template <>
struct EnumNames<AcceleratorKind> {
    static constexpr EnumName<AcceleratorKind> table[] = {{"embree", AcceleratorKind::Embree},
                                                           {"naive", AcceleratorKind::Naive}};
};

template <>
struct EnumNames<BuildQuality> {
    static constexpr EnumName<BuildQuality> table[] = {
        {"low", BuildQuality::Low}, {"medium", BuildQuality::Medium}, {"high", BuildQuality::High}};
};

template <>
struct EnumNames<PhongModel> {
    static constexpr EnumName<PhongModel> table[] = {{"classic", PhongModel::Classic},
                                                      {"normalized", PhongModel::Normalized},
                                                      {"normalised", PhongModel::Normalized, false}};
};

/// The value named `name`, or nullopt.
template <class E>
std::optional<E> enumFromName(std::string_view name) {
    for (const auto& entry : EnumNames<E>::table)
        if (entry.name == name) return entry.value;
    return std::nullopt;
}

/// The name of `value` ("" for a value outside the enum).
template <class E>
std::string_view enumName(E value) {
    for (const auto& entry : EnumNames<E>::table)
        if (entry.listed && entry.value == value) return entry.name;
    return {};
}

/// Every name, for messages: "auto, all, power or tree"; with quote = "\"",
/// "\"auto\", \"all\", \"power\" or \"tree\"".
template <class E>
std::string enumNameList(std::string_view quote = {}) {
    size_t n = 0;
    for (const auto& entry : EnumNames<E>::table) n += entry.listed;
    std::string list;
    size_t i = 0;
    for (const auto& entry : EnumNames<E>::table) {
        if (!entry.listed) continue;
        if (i) list += i + 1 == n ? " or " : ", ";
        list.append(quote).append(entry.name).append(quote);
        ++i;
    }
    return list;
}

}  // namespace pnb
