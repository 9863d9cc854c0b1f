// The one Penumbra error type: a code plus a message that names the file and
// the line or JSON path where that applies. Thrown at load, prepare or render
// time, never inside the per-ray path. It is the public pnb::Error itself
// (api/include/penumbra/types.hpp), so nothing is translated at the API.
#pragma once

#include <penumbra/types.hpp>

namespace penumbra {

using ErrorCode = pnb::ErrorCode;
using Error = pnb::Error;

}  // namespace penumbra
