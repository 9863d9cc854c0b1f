// The command-line values CLI11 cannot bind by itself: vectors and colours
// ("x,y,z"), crop windows, --env (a colour or a file) and seeds. Each parser
// throws std::invalid_argument with a message that leaves the option's name
// to the caller (CLI11 prefixes it: "--eye: expected x,y,z, got '1,2'").
#pragma once

#include <filesystem>
#include <string>
#include <variant>

#include <penumbra/penumbra.hpp>

namespace penumbra::cli {

/// "x,y,z": three finite numbers.
pnb::Vec3 parseVec3(const std::string& text);
/// "r,g,b": three finite numbers (their limits are the scene's: pnb::Scene checks them).
pnb::Color parseColor(const std::string& text);
/// "x0,y0,x1,y1": four pixel coordinates (the window is checked against the image size later).
pnb::CropWindow parseCrop(const std::string& text);

/// --env's value: an image file or a constant radiance. A value that names
/// an existing file, or holds a '/', is a file (so "./sky,1.pfm" is one even
/// before it exists); else a value with a comma is r,g,b (three finite
/// numbers >= 0); else a name with an image extension is a file.
std::variant<pnb::Color, std::filesystem::path> parseEnvironment(const std::string& text);

/// "" when `text` is a seed: a decimal integer in [0, 2^64 - 1], else what is
/// wrong with it (CLI11 would read "-1" as 2^64 - 1 and clamp larger values).
std::string seedProblem(const std::string& text);

}  // namespace penumbra::cli
