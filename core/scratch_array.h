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
#include <optional>
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

/// N empty std::optional<T>, each constructed in place by its default
/// constructor, which writes its engaged flag alone: GCC clears every byte
/// of a declared `std::optional<T> a[N]` (the optional's empty member is
/// value-initialised), 1 KiB for 16 hits, on every batch. For per-batch
/// result arrays that the accelerators assign or reset element by element.
template <class T, size_t N>
class EmptyOptionals {
    static_assert(std::is_trivially_destructible_v<std::optional<T>>, "nothing to destroy");

public:
    EmptyOptionals() {
        for (size_t i = 0; i < N; ++i) new (&bytes_[i * sizeof(std::optional<T>)]) std::optional<T>;
    }
    std::optional<T>& operator[](size_t i) { return data()[i]; }
    const std::optional<T>& operator[](size_t i) const { return data()[i]; }
    std::optional<T>* data() { return std::launder(reinterpret_cast<std::optional<T>*>(bytes_)); }
    const std::optional<T>* data() const {
        return std::launder(reinterpret_cast<const std::optional<T>*>(bytes_));
    }

private:
    alignas(std::optional<T>) unsigned char bytes_[N * sizeof(std::optional<T>)];
};

/// Storage for one T, constructed only by emplace() and then destroyed with
/// the holder. For a per-batch object that most batches never use:
/// a declared std::optional<T> clears every byte of its storage (GCC
/// value-initialises its empty member), 392 bytes for the integrator's 16
/// pending-ray stacks on every batch, used or not.
template <class T>
class Deferred {
public:
    Deferred() {}  // deliberately leaves the storage as it is
    ~Deferred() {
        if (value_) value_->~T();
    }
    Deferred(const Deferred&) = delete;
    Deferred& operator=(const Deferred&) = delete;
    /// Constructs the value (at most once).
    T& emplace() {
        if (!value_) value_ = new (bytes_) T();
        return *value_;
    }
    /// The value, or null before emplace().
    T* get() { return value_; }

private:
    alignas(T) unsigned char bytes_[sizeof(T)];
    T* value_ = nullptr;
};

}  // namespace penumbra
