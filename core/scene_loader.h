// The loaders moved to core/io/; this name stays for callers written against it.
#pragma once

#include "core/io/scene_loader.h"
