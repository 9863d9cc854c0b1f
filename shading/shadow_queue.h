// The one queue of shadow rays: the rays of a batch's shading points, traced
// 16 at a time as packets. Each ray carries the weight its sample adds if it
// is unoccluded and the lane it belongs to; flush() adds the weights of the
// unoccluded ones to their lanes' sums in the order they were queued, which
// is each lane's sample order, so a lane's sum does not depend on the other
// lanes in the batch.
#pragma once

#include <cstdint>
#include <span>

#include "accel/accelerator.h"
#include "core/color.h"
#include "core/ray.h"
#include "core/scratch_array.h"

namespace penumbra {

class ShadowQueue {
public:
    /// traced: the counter the traced rays are added to; sums: per lane.
    ShadowQueue(const Accelerator& accel, uint64_t& traced, Rgb* sums) : accel_(accel), traced_(traced), sums_(sums) {}
    ShadowQueue(const ShadowQueue&) = delete;
    ShadowQueue& operator=(const ShadowQueue&) = delete;

    /// Queues a ray whose weight goes to sums[lane] where it meets nothing.
    void add(size_t lane, const Ray& ray, const Rgb& weight) {
        rays_[pending_] = ray;
        weights_[pending_] = weight;
        lanes_[pending_] = static_cast<uint8_t>(lane);
        if (++pending_ == kPacket) flush();
    }

    /// Traces what is queued.
    void flush() {
        if (pending_ == 0) return;
        accel_.occludedBatch(std::span<const Ray>(rays_.data(), pending_), std::span<uint8_t>(blocked_, pending_));
        traced_ += pending_;
        for (uint32_t i = 0; i < pending_; ++i)
            if (!blocked_[i]) sums_[lanes_[i]] += weights_[i];
        pending_ = 0;
    }

private:
    static constexpr uint32_t kPacket = 16;
    const Accelerator& accel_;
    uint64_t& traced_;
    Rgb* sums_;
    ScratchArray<Ray, kPacket> rays_;
    ScratchArray<Rgb, kPacket> weights_;
    uint8_t lanes_[kPacket];
    uint8_t blocked_[kPacket];
    uint32_t pending_ = 0;
};

}  // namespace penumbra
