// Move-only owners of Embree handles, so a build that throws half-way releases
// whatever it had created. Only accel/ includes Embree headers.
#pragma once

#include <embree3/rtcore.h>

#include <utility>

namespace penumbra {

/// Owns one reference to an Embree object (device, scene or geometry) and
/// releases it with Release on destruction.
template <class Handle, void (*Release)(Handle)>
class EmbreeHandle {
public:
    EmbreeHandle() = default;
    explicit EmbreeHandle(Handle h) : h_(h) {}
    EmbreeHandle(const EmbreeHandle&) = delete;
    EmbreeHandle& operator=(const EmbreeHandle&) = delete;
    EmbreeHandle(EmbreeHandle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
    EmbreeHandle& operator=(EmbreeHandle&& o) noexcept {
        if (this != &o) {
            reset();
            h_ = std::exchange(o.h_, nullptr);
        }
        return *this;
    }
    ~EmbreeHandle() { reset(); }

    /// The raw handle (nullptr when empty).
    Handle get() const { return h_; }
    explicit operator bool() const { return h_ != nullptr; }

    /// Releases the held reference now.
    void reset() {
        if (h_) Release(std::exchange(h_, nullptr));
    }

private:
    Handle h_ = nullptr;
};

using EmbreeDevice = EmbreeHandle<RTCDevice, rtcReleaseDevice>;
using EmbreeScene = EmbreeHandle<RTCScene, rtcReleaseScene>;
using EmbreeGeometry = EmbreeHandle<RTCGeometry, rtcReleaseGeometry>;

}  // namespace penumbra
