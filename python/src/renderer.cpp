// Renderer (load, prepare, render, progressive passes) and RenderJob
// (asynchronous renders). Every render runs without the GIL.
#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "bindings.h"
#include "wait.h"

namespace pnbpy {

namespace {

using namespace std::chrono_literals;

bool interpreterAlive() {
#if PY_VERSION_HEX >= 0x030D0000
    return Py_IsInitialized() && !Py_IsFinalizing();
#else
    return Py_IsInitialized() && !_Py_IsFinalizing();
#endif
}

// A Python exception from a callback on a library thread, as the pnb::Error
// that the library passes back to its caller (the job's error).
[[noreturn]] void callbackFailed(const char* which, py::error_already_set& e) {
    std::string what = e.what();  // "Type: message", then pybind11's traceback: keep the first line
    what = what.substr(0, what.find('\n'));
    throw pnb::Error(pnb::ErrorCode::Internal, std::string(which) + " callback raised " + what);
}

// prepare()'s accelerator: an AcceleratorKind, or its name as the command line spells it.
pnb::AcceleratorKind acceleratorFrom(const py::handle& value) { return enumFrom<pnb::AcceleratorKind>(value, "accelerator"); }

// ---- resolving the arguments every render takes

struct RenderArgs {
    pnb::PreparedScene scene;
    pnb::Camera camera;
    pnb::RenderSettings settings;
};

pnb::PreparedScene preparedFrom(const pnb::Renderer& r, const py::object& scene) {
    if (py::isinstance<pnb::PreparedScene>(scene)) return scene.cast<pnb::PreparedScene>();
    if (py::isinstance<pnb::Scene>(scene)) {
        const pnb::Scene& s = scene.cast<const pnb::Scene&>();
        py::gil_scoped_release release;
        return r.prepare(s);
    }
    throw py::type_error("expected a penumbra.Scene or penumbra.PreparedScene, got " +
                         std::string(py::str(scene.get_type().attr("__name__"))));
}

// Settings: `settings` or the scene file's, then the keywords; with a
// framebuffer and no settings, its size, window and AOVs. Camera: `camera`,
// the scene's, or one framing the scene (as the CLI does).
RenderArgs argsFrom(const pnb::Renderer& r, const py::object& scene, const py::object& camera,
                    const py::object& settings, const py::kwargs& kw, const PyFramebuffer* fb = nullptr) {
    RenderArgs a;
    a.scene = preparedFrom(r, scene);
    pnb::RenderSettings base = settings.is_none() ? a.scene.settings() : settings.cast<pnb::RenderSettings>();
    if (fb && settings.is_none()) {
        base.width = fb->fb.fullWidth();
        base.height = fb->fb.fullHeight();
        const pnb::CropWindow w = fb->fb.window();
        if (w.x0 != 0 || w.y0 != 0 || w.x1 != base.width || w.y1 != base.height) base.crop = w;
        else base.crop.reset();
        base.aovs = fb->fb.hasAovs();
    }
    a.settings = settingsWith(base, kw);
    if (!camera.is_none()) {
        a.camera = camera.cast<pnb::Camera>();
    } else {
        pnb::validate(a.settings);  // a bad size would make a bad aspect ratio
        a.camera = a.scene.defaultCamera(float(a.settings.width) / float(a.settings.height));
    }
    return a;
}

// ---- logging

pnb::LogCallback logCallback(const py::object& fn) {
    if (fn.is_none()) return {};
    PyCallable cb(fn);
    return [cb](pnb::LogLevel level, std::string_view message) {
        if (!interpreterAlive()) return;
        py::gil_scoped_acquire gil;
        try {
            cb.get()(level, py::str(message.data(), message.size()));
        } catch (py::error_already_set& e) {
            e.discard_as_unraisable("penumbra log callback");
        }
    };
}

// ---- asynchronous jobs

// What a job's callbacks and its PyJob share: the job's identity.
struct JobToken {};

// The jobs whose callbacks run on this thread (a library thread), innermost
// last. Python code there may drop the last reference to a job, whose
// destructor joins that very thread (or waits for the render this thread
// works for): such a job is destroyed on a thread of its own instead. And it
// may wait for its own job, which cannot end before the callback returns:
// that raises, as Thread.join() on the current thread does.
thread_local std::vector<const JobToken*> callbackJobs;

struct InJobCallback {
    explicit InJobCallback(const JobToken* job) { callbackJobs.push_back(job); }
    ~InJobCallback() { callbackJobs.pop_back(); }
    InJobCallback(const InJobCallback&) = delete;
    InJobCallback& operator=(const InJobCallback&) = delete;
};

struct PyJob {
    pnb::RenderJob job;
    std::shared_ptr<const JobToken> token;
    std::shared_ptr<PyFramebuffer> image;  // taken out of the job on first request

    PyJob() = default;
    PyJob(const PyJob&) = delete;
    PyJob& operator=(const PyJob&) = delete;
    // Destroying a running job cancels and joins it; its thread may be
    // waiting for the GIL (a callback), so give it up meanwhile.
    ~PyJob() {
        if (!callbackJobs.empty()) {
            std::thread([j = std::move(job)]() mutable { j = pnb::RenderJob(); }).detach();
            return;
        }
        if (Py_IsInitialized() && PyGILState_Check()) {
            py::gil_scoped_release release;
            job = pnb::RenderJob();
        }
    }

    // Raises RuntimeError inside one of this job's own callbacks.
    void refuseWaitFromOwnCallback() const {
        if (std::find(callbackJobs.begin(), callbackJobs.end(), token.get()) != callbackJobs.end())
            throw std::runtime_error(
                "cannot wait for a render job inside its own progress, on_pass or on_complete callback: the job "
                "ends only after the callback returns");
    }

    // Waits with the GIL released, polling for Ctrl-C (which cancels the job).
    bool wait(std::optional<double> timeoutSeconds) {
        refuseWaitFromOwnCallback();
        const auto deadline = std::chrono::steady_clock::now() +
                              std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(timeoutSeconds.value_or(0.0)));
        for (;;) {
            bool done;
            {
                py::gil_scoped_release release;
                done = job.waitFor(kPollInterval);
            }
            if (PyErr_CheckSignals() != 0) {
                py::error_already_set interrupt;
                job.cancel();
                {
                    py::gil_scoped_release release;
                    job.wait();
                }
                throw interrupt;
            }
            if (done) return true;
            if (timeoutSeconds && std::chrono::steady_clock::now() >= deadline) return false;
        }
    }

    std::shared_ptr<PyFramebuffer> framebuffer() {
        wait(std::nullopt);
        if (!image) image = std::make_shared<PyFramebuffer>(job.takeFramebuffer());  // throws the job's error
        return image;
    }
};

pnb::AsyncOptions asyncOptions(const std::shared_ptr<const JobToken>& job, std::uint32_t passSamples,
                               const py::object& progress, const py::object& onPass, const py::object& onComplete) {
    pnb::AsyncOptions o;
    o.passSamples = passSamples;
    if (!progress.is_none()) {
        PyCallable cb(progress);
        o.progress = [cb, job](double f) {
            if (!interpreterAlive()) return;  // at exit: nobody to call
            InJobCallback inCallback(job.get());
            py::gil_scoped_acquire gil;
            try {
                cb.get()(f);
            } catch (py::error_already_set& e) {
                callbackFailed("progress", e);
            }
        };
    }
    if (!onPass.is_none()) {
        PyCallable cb(onPass);
        o.onPass = [cb, job](const pnb::Framebuffer& image, std::uint32_t samplesDone) {
            if (!interpreterAlive()) return;  // at exit: nobody to call
            auto copy = std::make_shared<PyFramebuffer>(image);  // the job's own image is lent only for the call
            InJobCallback inCallback(job.get());
            py::gil_scoped_acquire gil;
            try {
                cb.get()(std::move(copy), samplesDone);
            } catch (py::error_already_set& e) {
                callbackFailed("on_pass", e);
            }
        };
    }
    if (!onComplete.is_none()) {
        PyCallable cb(onComplete);
        o.onComplete = [cb, job](const pnb::JobResult& r) {
            if (!interpreterAlive()) return;  // at exit: nobody to call
            std::shared_ptr<PyFramebuffer> image;
            if (r.framebuffer) image = std::make_shared<PyFramebuffer>(*r.framebuffer);
            InJobCallback inCallback(job.get());
            py::gil_scoped_acquire gil;
            try {
                py::object result = py::module_::import("types").attr("SimpleNamespace")(
                    py::arg("status") = r.status, py::arg("error") = r.error ? errorObject(*r.error) : py::none(),
                    py::arg("stats") = r.stats, py::arg("image") = image ? makeImage(image, r.stats) : py::none());
                cb.get()(result);
            } catch (py::error_already_set& e) {
                e.discard_as_unraisable("penumbra on_complete callback");
            }
        };
    }
    return o;
}

void bindJob(py::module_& m) {
    py::class_<PyJob>(m, "RenderJob",
                      "A render running on a thread of its own (Renderer.render_async). Deleting it cancels the "
                      "render and waits for it; `with renderer.render_async(...) as job:` does the same on exit.")
        .def_property_readonly("progress", [](const PyJob& j) { return j.job.progress(); }, "fraction done, 0 to 1")
        .def_property_readonly("done", [](const PyJob& j) { return j.job.done(); })
        .def_property_readonly("status", [](const PyJob& j) { return j.job.status(); })
        .def("cancel", [](PyJob& j) { j.job.cancel(); }, "Asks the render to stop; it does within a fraction of a second.")
        .def("wait", &PyJob::wait, py::arg("timeout") = py::none(),
             "Waits (at most `timeout` seconds) for the job to end; returns whether it has. Ctrl-C cancels the "
             "job and raises KeyboardInterrupt.")
        .def_property_readonly(
            "error",
            [](PyJob& j) -> py::object {
                j.wait(std::nullopt);
                const std::optional<pnb::Error> e = j.job.error();
                return e ? errorObject(*e) : py::none();
            },
            "Waits; the penumbra.Error of a cancelled or failed job, else None.")
        .def_property_readonly("stats", [](PyJob& j) {
            j.wait(std::nullopt);
            return j.job.stats();
        })
        .def_property_readonly("framebuffer", &PyJob::framebuffer,
                               "Waits; the finished Framebuffer (raises the job's penumbra.Error otherwise).")
        .def(
            "result",
            [](PyJob& j, std::optional<double> timeout) {
                if (!j.wait(timeout)) throw py::value_error("the render job is still running after the timeout");
                return makeImage(j.framebuffer(), j.job.stats());
            },
            py::arg("timeout") = py::none(),
            "Waits; the image as Renderer.render returns it. Raises the job's penumbra.Error (code Cancelled "
            "for a cancelled job).")
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__",
             [](PyJob& j, const py::args&) {
                 j.refuseWaitFromOwnCallback();
                 j.job.cancel();
                 py::gil_scoped_release release;
                 j.job.wait();
             })
        .def("__repr__", [](const PyJob& j) {
            static const char* names[] = {"running", "finished", "cancelled", "failed"};
            return "<penumbra.RenderJob " + std::string(names[int(j.job.status())]) + ", " +
                   std::to_string(int(j.job.progress() * 100.0 + 0.5)) + "%>";
        });
}

const char* kSettingsDoc =
    "Settings are `settings` (a RenderSettings) or else the scene file's, changed by the keywords width, "
    "height, spp, light_samples, max_depth, seed, threads, tile_size, crop=(x0, y0, x1, y1), "
    "light_selection ('auto', 'all', 'power' or 'tree'), aovs, integrator ('whitted' or 'path'). The camera is `camera`, else the scene's, else one framing the "
    "scene. `scene` is a PreparedScene (or a Scene, prepared for this call). `progress(fraction)` is called on "
    "this thread while the render runs; setting the `cancel` event (threading.Event) or Ctrl-C stops it.";

}  // namespace

PyCallable::PyCallable(py::object fn)
    : fn_(new py::object(std::move(fn)), [](py::object* p) {
          if (!interpreterAlive()) {
              p->release();  // too late to decrement: leak the reference
              delete p;
              return;
          }
          py::gil_scoped_acquire gil;
          delete p;
      }) {}

void bindRenderer(py::module_& m) {
    bindJob(m);

    py::class_<pnb::Renderer>(m, "Renderer",
                              "Loads, prepares and renders. Holds no scene; renderers are independent and their "
                              "methods may be called from several threads at once.")
        .def(py::init([](const py::object& log, pnb::LogLevel level) {
                 return pnb::Renderer(logCallback(log), level);
             }),
             py::arg("log") = py::none(), py::arg("log_level") = pnb::LogLevel::Warning,
             "Without `log`, warnings and errors go to stderr; else log(level, message) gets messages of at "
             "least log_level (possibly from render threads, with the GIL taken for the call).")
        .def("set_log",
             [](pnb::Renderer& r, const py::object& log, pnb::LogLevel level) { r.setLog(logCallback(log), level); },
             py::arg("log"), py::arg("log_level") = pnb::LogLevel::Warning)
        .def(
            "load_scene",
            [](const pnb::Renderer& r, const py::object& path, bool strict, bool restrictPaths,
               const std::vector<py::object>& allowedRoots, std::optional<pnb::PhongModel> model, float smoothAngle) {
                pnb::LoadOptions o;
                o.strict = strict;
                o.restrictPaths = restrictPaths;
                o.meshModel = model;
                o.smoothAngleDegrees = smoothAngle;
                for (const py::object& root : allowedRoots) o.allowedRoots.push_back(pathString(root));
                const std::string p = pathString(path);
                py::gil_scoped_release release;
                return r.loadScene(p, o);
            },
            py::arg("path"), py::kw_only(), py::arg("strict") = false, py::arg("restrict_paths") = true,
            py::arg("allowed_roots") = std::vector<py::object>{}, py::arg("model") = py::none(),
            py::arg("smooth_angle") = 30.f,
            "Reads a .json, .obj or model scene (PLY, STL, glTF, FBX, COLLADA, ... through Assimp). With "
            "restrict_paths (the default) only files below the scene's folder and allowed_roots may be read. "
            "model (a PhongModel) sets the Phong model of mesh files' materials; meshes without normals are "
            "smoothed across edges under smooth_angle degrees (0 = faceted). Raises penumbra.Error naming the "
            "file and line or JSON path.")
        .def(
            "prepare",
            [](const pnb::Renderer& r, const pnb::Scene& scene, const py::object& accelerator,
               pnb::BuildQuality quality) {
                pnb::PrepareOptions o;
                o.accelerator = acceleratorFrom(accelerator);
                o.quality = quality;
                py::gil_scoped_release release;
                return r.prepare(scene, o);
            },
            py::arg("scene"), py::kw_only(), py::arg("accelerator") = pnb::AcceleratorKind::Embree,
            py::arg("quality") = pnb::BuildQuality::High,
            "Validates the scene (repairs are logged and counted), builds its BVH and light tables. "
            "accelerator: AcceleratorKind.Embree or .Naive (or 'embree', 'naive').")
        .def(
            "update",
            [](const pnb::Renderer& r, const pnb::PreparedScene& prepared,
               const std::map<std::size_t, pnb::Matrix3x4>& transforms,
               const std::map<pnb::MaterialId, pnb::Material>& materials,
               const std::map<std::size_t, pnb::Color>& pointLights,
               const std::map<std::size_t, pnb::Color>& directionalLights, std::optional<float> environmentRotation,
               std::optional<float> environmentScale) {
                pnb::SceneEdits e;
                e.transforms.assign(transforms.begin(), transforms.end());
                e.materials.assign(materials.begin(), materials.end());
                e.pointLights.assign(pointLights.begin(), pointLights.end());
                e.directionalLights.assign(directionalLights.begin(), directionalLights.end());
                e.environmentRotateDegrees = environmentRotation;
                e.environmentScale = environmentScale;
                py::gil_scoped_release release;
                return r.update(prepared, e);
            },
            py::arg("prepared"), py::kw_only(), py::arg("transforms") = std::map<std::size_t, pnb::Matrix3x4>{},
            py::arg("materials") = std::map<pnb::MaterialId, pnb::Material>{},
            py::arg("point_lights") = std::map<std::size_t, pnb::Color>{},
            py::arg("directional_lights") = std::map<std::size_t, pnb::Color>{},
            py::arg("environment_rotation") = py::none(), py::arg("environment_scale") = py::none(),
            "A new PreparedScene: `prepared` with edits applied, the same image bit for bit as preparing the "
            "edited Scene, sharing what the edits leave alone (moving instances rebuilds only the top-level BVH). "
            "transforms: {instance index (add_instance's result): Matrix3x4}; materials: {material id: Material}; "
            "point_lights / directional_lights: {index in the order added: intensity / irradiance}; "
            "environment_rotation (degrees about +y) and environment_scale. Raises penumbra.Error naming a bad "
            "edit; `prepared` is never changed.")
        .def(
            "render",
            [](const pnb::Renderer& r, const py::object& scene, const py::object& camera, const py::object& settings,
               const std::shared_ptr<PyFramebuffer>& framebuffer, const py::object& progress,
               const py::object& cancel, const py::kwargs& kw) {
                const RenderArgs a = argsFrom(r, scene, camera, settings, kw, framebuffer.get());
                std::shared_ptr<PyFramebuffer> fb = framebuffer;
                if (!fb) {
                    py::gil_scoped_release release;
                    fb = std::make_shared<PyFramebuffer>(pnb::Framebuffer(a.settings));
                }
                pnb::RenderStats stats;
                {
                    BusyLease lease(*fb);
                    pnb::Framebuffer& image = fb->fb;
                    stats = runWaiting(
                        [&](const pnb::RenderControl& c) { return r.render(a.scene, a.camera, a.settings, image, c); },
                        progress, cancel);
                }
                // The image keeps its own copy of a host's framebuffer, which later passes may change.
                return makeImage(framebuffer ? std::make_shared<PyFramebuffer>(fb->fb) : fb, stats);
            },
            py::arg("scene"), py::arg("camera") = py::none(), py::arg("settings") = py::none(), py::kw_only(),
            py::arg("framebuffer") = py::none(), py::arg("progress") = py::none(), py::arg("cancel") = py::none(),
            (std::string("Renders all spp samples and returns a penumbra.Image: a float32 numpy array (H, W, 3) of "
                         "linear radiance, (H, W, 10) with aovs=True (R G B, albedo, normal, depth), row 0 on top; "
                         "bit-identical to the CLI's EXR for the same scene and settings. With framebuffer=, "
                         "renders the samples it is missing into it (size, crop and AOVs default to its own). ") +
             kSettingsDoc)
                .c_str())
        .def(
            "render_pass",
            [](const pnb::Renderer& r, const py::object& scene, PyFramebuffer& fb, std::uint32_t firstSample,
               std::uint32_t sampleCount, const py::object& camera, const py::object& settings,
               const py::object& progress, const py::object& cancel, const py::kwargs& kw) {
                const RenderArgs a = argsFrom(r, scene, camera, settings, kw, &fb);
                BusyLease lease(fb);
                pnb::Framebuffer& image = fb.fb;
                return runWaiting(
                    [&](const pnb::RenderControl& c) {
                        return r.renderPass(a.scene, a.camera, a.settings, image, firstSample, sampleCount, c);
                    },
                    progress, cancel);
            },
            py::arg("scene"), py::arg("framebuffer"), py::arg("first_sample"), py::arg("sample_count"),
            py::arg("camera") = py::none(), py::arg("settings") = py::none(), py::kw_only(),
            py::arg("progress") = py::none(), py::arg("cancel") = py::none(),
            (std::string("One progressive pass: adds samples [first_sample, first_sample + sample_count) of the "
                         "spp-sample set to `framebuffer`, which must hold exactly first_sample samples. Passes "
                         "covering [0, spp) give the one-shot image bit for bit. Returns RenderStats. ") +
             kSettingsDoc)
                .c_str())
        .def(
            "render_async",
            [](const pnb::Renderer& r, const py::object& scene, const py::object& camera, const py::object& settings,
               std::uint32_t passSamples, const py::object& progress, const py::object& onPass,
               const py::object& onComplete, const py::kwargs& kw) {
                const RenderArgs a = argsFrom(r, scene, camera, settings, kw);
                auto job = std::make_unique<PyJob>();
                job->token = std::make_shared<JobToken>();
                pnb::AsyncOptions o = asyncOptions(job->token, passSamples, progress, onPass, onComplete);
                job->job = r.renderAsync(a.scene, a.camera, a.settings, std::move(o));
                return job;
            },
            py::arg("scene"), py::arg("camera") = py::none(), py::arg("settings") = py::none(), py::kw_only(),
            py::arg("pass_samples") = 0, py::arg("progress") = py::none(), py::arg("on_pass") = py::none(),
            py::arg("on_complete") = py::none(),
            "Starts rendering on a thread of its own and returns a RenderJob at once. progress(fraction) runs "
            "on render threads; with pass_samples > 0, on_pass(framebuffer_copy, samples_done) runs after each "
            "progressive pass; on_complete(result) once at the end (result.status, .error, .stats, .image). "
            "Callbacks take the GIL only while they run; an exception in progress or on_pass fails the job. "
            "Settings and camera as for render().");
}

}  // namespace pnbpy
