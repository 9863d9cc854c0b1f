/* Penumbra version, for C and C++ hosts. Kept equal to project(VERSION) in the
 * top-level CMakeLists.txt; cmake/PenumbraInstall.cmake checks that at configure time. */
#ifndef PENUMBRA_VERSION_H
#define PENUMBRA_VERSION_H

#define PENUMBRA_VERSION_MAJOR 0
#define PENUMBRA_VERSION_MINOR 1
#define PENUMBRA_VERSION_PATCH 0
#define PENUMBRA_VERSION "0.1.0"

/* One comparable number: major * 10000 + minor * 100 + patch. */
#define PENUMBRA_VERSION_NUMBER (PENUMBRA_VERSION_MAJOR * 10000 + PENUMBRA_VERSION_MINOR * 100 + PENUMBRA_VERSION_PATCH)

#endif /* PENUMBRA_VERSION_H */
