// Which files the loaders may read: the bottom of core/io. Every loader asks
// here (through openInputFile) and nothing here knows any file format.
#pragma once

#include <filesystem>

#include "core/io/load_options.h"

namespace penumbra {

/// Checks `file` against options.allowedRoots; throws Error(InvalidArgument)
/// naming the file when it lies outside all of them. When unrestricted, only
/// reports files outside options.noticeRoots (if any) to options.onReadOutside.
/// `willRead` = false for checks made before probing the file system (the
/// file actually read is checked again), so each read is reported once.
void checkPathAllowed(const std::filesystem::path& file, const LoadOptions& options, bool willRead = true);

}  // namespace penumbra
