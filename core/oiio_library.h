// Finds and loads libpenumbra_oiio.so (OpenImageIO behind core/oiio/oiio_api.h)
// on the first image a process reads or writes.
#pragma once

#include "core/oiio/oiio_api.h"

namespace penumbra {

/// The image module's functions. Loaded once per process on first use from
/// the folder of the object that holds this code (libpenumbra.so, or an
/// executable linking the objects: then its ../lib), then the dynamic
/// linker's search path. Throws Error(IoError) saying where it looked.
/// Thread-safe.
const oiio::Api& oiioLibrary();

}  // namespace penumbra
