// What the pieces of the C API share: the handle structs, the guard that turns
// every exception into a status and a message, and the conversions between
// the C structs and the C++ API's values (api/c_api_types.cpp). Internal to api/.
#pragma once

#include <penumbra/penumbra.h>

#include <atomic>
#include <cstring>
#include <new>
#include <penumbra/penumbra.hpp>
#include <string>
#include <utility>

#include <memory>

struct pnb_renderer {
    pnb::Renderer renderer;
    std::string error;
};

struct pnb_scene {
    pnb::Scene scene;
    std::string error;
};

struct pnb_prepared_scene {
    pnb::PreparedScene prepared;
};

struct pnb_framebuffer {
    pnb::Framebuffer owned;
    const pnb::Framebuffer* borrowed = nullptr;  // a job's or a callback's image: read-only
    mutable std::string error;
    const pnb::Framebuffer& get() const { return borrowed ? *borrowed : owned; }
};

struct pnb_render_job {
    pnb::RenderJob job;
    pnb_framebuffer image;  // borrows the job's image once it finished
    std::string error;
};


namespace pnb::c_api {


// The per-thread fallback for failures without a handle to keep them.
inline std::string& lastErrorSlot() {
    thread_local std::string slot;
    return slot;
}

// A C caller may store any int in an enum field; in C++ reading an enum object
// outside its value range is undefined, so the raw bits are read instead.
template <class E>
inline int rawEnum(const E& e) {
    static_assert(sizeof(E) == sizeof(int), "C enums are int-sized");
    int v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

inline pnb_status toStatus(pnb::ErrorCode code) { return static_cast<pnb_status>(static_cast<int>(code)); }

inline pnb_status record(std::string* sink, pnb_status status, const char* function, const char* message) noexcept {
    try {
        std::string text(function);
        text += ": ";
        text += message;
        if (sink) *sink = text;
        lastErrorSlot() = std::move(text);
    } catch (...) {
        // Out of memory while reporting: the status code still tells what happened.
    }
    return status;
}

// Runs f, turning every exception into a status and a recorded message.
template <class F>
pnb_status guard(std::string* sink, const char* function, F&& f) noexcept {
    try {
        f();
        return PNB_OK;
    } catch (const pnb::Error& e) {
        return record(sink, toStatus(e.code()), function, e.what());
    } catch (const std::bad_alloc&) {
        return record(sink, PNB_ERROR_OUT_OF_MEMORY, function, "out of memory");
    } catch (const std::exception& e) {
        return record(sink, PNB_ERROR_INTERNAL, function, e.what());
    } catch (...) {
        return record(sink, PNB_ERROR_INTERNAL, function, "unknown exception");
    }
}

// Throws the InvalidArgument error guard() reports for a NULL argument.
inline void need(const void* p, const char* what) {
    if (!p) throw pnb::Error(pnb::ErrorCode::InvalidArgument, std::string(what) + " is NULL");
}

// A synchronous render's hooks: the C progress callback cancels by returning nonzero.
struct SyncControl {
    std::atomic<bool> cancel{false};
    pnb::RenderControl control;
    explicit SyncControl(const pnb_render_callbacks* cb) {
        if (!cb || !cb->progress) return;
        control.cancel = &cancel;
        control.progress = [this, fn = cb->progress, user = cb->user](double f) {
            if (fn(f, user) != 0) cancel.store(true);
        };
    }
};

template <class T>
inline void destroy(T* p) noexcept {
    delete p;
}

// Conversions (api/c_api_types.cpp, where the static_asserts tie each C struct to its C++ value).
pnb::Vec3 in(pnb_vec3 v);
pnb_vec3 out(const pnb::Vec3& v);
pnb::Color in(pnb_color c);
pnb_color out(const pnb::Color& c);
pnb::Camera in(const pnb_camera& c);
pnb_camera out(const pnb::Camera& c);
pnb::RenderSettings in(const pnb_render_settings& s);
pnb_render_settings out(const pnb::RenderSettings& s);
pnb_render_stats out(const pnb::RenderStats& s);

}  // namespace pnb::c_api
