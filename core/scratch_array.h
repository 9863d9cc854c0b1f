// Fixed-size scratch storage whose elements are not initialised on
// construction: the renderer's per-batch queues and sums, rebuilt for every
// batch of 16 camera samples, where zeroing arrays that are written before
// they are read cost more than the work they hold (shadow queues: 16 rays
// and weights per call). Only for implicit-lifetime value types (trivially
// copyable and destructible), whose objects come into existence with the
// storage; read an element only after writing it, and never hand one to
// code that assigns through it (std::optional's assignment reads its own
// engaged flag: construct those).
#pragma once

#include <cstddef>
#include <new>
#include <type_traits>

namespace penumbra {

template <class T, size_t N>
class ScratchArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "ScratchArray holds plain values only");

public:
    ScratchArray() {}  // deliberately leaves the storage as it is
    T& operator[](size_t i) { return data()[i]; }
    const T& operator[](size_t i) const { return data()[i]; }
    T* data() { return std::launder(reinterpret_cast<T*>(bytes_)); }
    const T* data() const { return std::launder(reinterpret_cast<const T*>(bytes_)); }
    static constexpr size_t size() { return N; }

private:
    alignas(T) unsigned char bytes_[N * sizeof(T)];
};

}  // namespace penumbra
