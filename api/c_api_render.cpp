// The C API's framebuffers, renders and asynchronous jobs (see api/c_api.cpp).
#include "api/c_api_internal.h"

#include <cstdlib>

using namespace pnb::c_api;

namespace {
pnb::ImageOptions imageOptions(const pnb_image_options* options) {
    pnb::ImageOptions o;
    if (options) {
        o.exposure = options->exposure;
        o.aovs = options->aovs != 0;
    }
    return o;
}
}  // namespace

extern "C" {

// ---------------------------------------------------------------- framebuffer

pnb_status pnb_framebuffer_create(const pnb_render_settings* settings, pnb_framebuffer** out) {
    if (out) *out = nullptr;
    return guard(nullptr, "pnb_framebuffer_create", [&] {
        need(settings, "settings");
        need(out, "out");
        auto image = std::make_unique<pnb_framebuffer>();
        image->owned = pnb::Framebuffer(in(*settings));
        *out = image.release();
    });
}

void pnb_framebuffer_destroy(pnb_framebuffer* image) {
    if (image && !image->borrowed) delete image;  // borrowed images belong to their job
}

const char* pnb_framebuffer_last_error(const pnb_framebuffer* image) { return image ? image->error.c_str() : ""; }
int pnb_framebuffer_width(const pnb_framebuffer* image) { return image ? image->get().width() : 0; }
int pnb_framebuffer_height(const pnb_framebuffer* image) { return image ? image->get().height() : 0; }
uint32_t pnb_framebuffer_sample_count(const pnb_framebuffer* image) { return image ? image->get().sampleCount() : 0; }

pnb_status pnb_framebuffer_read_rgba(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_rgba", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readRgba(dst, count);
    });
}

pnb_status pnb_framebuffer_read_albedo(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_albedo", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readAlbedo(dst, count);
    });
}

pnb_status pnb_framebuffer_read_normals(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_normals", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readNormals(dst, count);
    });
}

pnb_status pnb_framebuffer_read_depth(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_depth", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readDepth(dst, count);
    });
}

pnb_status pnb_framebuffer_pixel(const pnb_framebuffer* image, int x, int y, pnb_color* out) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_pixel", [&] {
        need(image, "framebuffer");
        need(out, "out");
        *out = ::out(image->get().pixel(x, y));
    });
}

pnb_status pnb_framebuffer_clear(pnb_framebuffer* image) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_clear", [&] {
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        image->owned.clear();
    });
}

pnb_status pnb_framebuffer_write_image(const pnb_framebuffer* image, const char* path,
                                       const pnb_image_options* options) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_write_image", [&] {
        need(image, "framebuffer");
        need(path, "path");
        image->get().writeImage(path, imageOptions(options));
    });
}

pnb_status pnb_framebuffer_encode_image(const pnb_framebuffer* image, const char* format,
                                        const pnb_image_options* options, uint8_t** out_data, size_t* out_size) {
    if (out_data) *out_data = nullptr;
    if (out_size) *out_size = 0;
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_encode_image", [&] {
        need(image, "framebuffer");
        need(format, "format");
        need(out_data, "out_data");
        need(out_size, "out_size");
        const std::vector<std::uint8_t> bytes = image->get().encodeImage(format, imageOptions(options));
        // malloc'd, so that a host in C frees it without knowing C++ (pnb_bytes_free).
        auto* data = static_cast<uint8_t*>(std::malloc(bytes.empty() ? 1 : bytes.size()));
        if (!data) throw std::bad_alloc();
        std::memcpy(data, bytes.data(), bytes.size());
        *out_data = data;
        *out_size = bytes.size();
    });
}

void pnb_bytes_free(uint8_t* data) { std::free(data); }

// ---------------------------------------------------------------- rendering

pnb_status pnb_render(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                      const pnb_render_settings* settings, pnb_framebuffer* image,
                      const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        SyncControl control(callbacks);
        const pnb::RenderStats st =
            renderer->renderer.render(prepared->prepared, in(*camera), in(*settings), image->owned, control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_rgba(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                           const pnb_render_settings* settings, float* rgba, size_t count,
                           const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_rgba", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(rgba, "rgba");
        SyncControl control(callbacks);
        const pnb::RenderStats st =
            renderer->renderer.render(prepared->prepared, in(*camera), in(*settings), rgba, count, control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_pass(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                           const pnb_render_settings* settings, pnb_framebuffer* image, uint32_t first_sample,
                           uint32_t sample_count, const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_pass", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        SyncControl control(callbacks);
        const pnb::RenderStats st = renderer->renderer.renderPass(prepared->prepared, in(*camera), in(*settings),
                                                                  image->owned, first_sample, sample_count,
                                                                  control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_async(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                            const pnb_render_settings* settings, const pnb_async_options* options,
                            pnb_render_job** out) {
    if (out) *out = nullptr;
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_async", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(out, "out");
        pnb::AsyncOptions ao;
        if (options) {
            const pnb_async_options o = *options;
            ao.passSamples = o.pass_samples;
            if (o.progress) ao.progress = [o](double f) { o.progress(f, o.user); };
            if (o.on_pass)
                ao.onPass = [o](const pnb::Framebuffer& image, uint32_t done) {
                    pnb_framebuffer view;
                    view.borrowed = &image;
                    o.on_pass(&view, done, o.user);
                };
            if (o.on_complete)
                ao.onComplete = [o](const pnb::JobResult& r) {
                    pnb_framebuffer view;
                    view.borrowed = r.framebuffer;
                    const pnb_status status = r.error ? toStatus(r.error->code()) : PNB_OK;
                    o.on_complete(status, r.error ? r.error->what() : "", r.framebuffer ? &view : nullptr, o.user);
                };
        }
        auto job = std::make_unique<pnb_render_job>();
        job->job = renderer->renderer.renderAsync(prepared->prepared, in(*camera), in(*settings), std::move(ao));
        *out = job.release();
    });
}

double pnb_render_job_progress(const pnb_render_job* job) { return job ? job->job.progress() : 0.0; }

pnb_status pnb_render_job_cancel(pnb_render_job* job) {
    return guard(nullptr, "pnb_render_job_cancel", [&] {
        need(job, "job");
        job->job.cancel();
    });
}

int pnb_render_job_done(const pnb_render_job* job) { return job && job->job.done() ? 1 : 0; }

pnb_status pnb_render_job_wait(pnb_render_job* job) {
    if (!job) return record(nullptr, PNB_ERROR_INVALID_ARGUMENT, "pnb_render_job_wait", "job is NULL");
    pnb_status status = PNB_OK;
    const pnb_status called = guard(&job->error, "pnb_render_job_wait", [&] {
        const std::optional<pnb::Error> e = job->job.error();  // waits
        if (e) status = record(&job->error, toStatus(e->code()), "pnb_render_job_wait", e->what());
    });
    return called != PNB_OK ? called : status;
}

pnb_status pnb_render_job_wait_for(pnb_render_job* job, uint32_t timeout_ms, int* done) {
    return guard(job ? &job->error : nullptr, "pnb_render_job_wait_for", [&] {
        need(job, "job");
        const bool finished = job->job.waitFor(std::chrono::milliseconds(timeout_ms));
        if (done) *done = finished ? 1 : 0;
    });
}

pnb_status pnb_render_job_framebuffer(pnb_render_job* job, const pnb_framebuffer** out) {
    if (out) *out = nullptr;
    return guard(job ? &job->error : nullptr, "pnb_render_job_framebuffer", [&] {
        need(job, "job");
        need(out, "out");
        job->image.borrowed = &job->job.framebuffer();  // waits; throws the job's error
        *out = &job->image;
    });
}

pnb_status pnb_render_job_stats(pnb_render_job* job, pnb_render_stats* out) {
    return guard(job ? &job->error : nullptr, "pnb_render_job_stats", [&] {
        need(job, "job");
        need(out, "out");
        *out = ::out(job->job.stats());
    });
}

void pnb_render_job_destroy(pnb_render_job* job) { destroy(job); }
const char* pnb_render_job_last_error(const pnb_render_job* job) { return job ? job->error.c_str() : ""; }

}  // extern "C"
