// Running a blocking library call without the GIL while the calling thread
// stays responsive to Python: Ctrl-C, a cancel event and progress callbacks.
#pragma once

#include "bindings.h"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

namespace pnbpy {

/// How often the waiting thread takes the GIL to check for signals, the
/// cancel event and progress. Short against a human's Ctrl-C, long against
/// the cost of taking the GIL.
inline constexpr std::chrono::milliseconds kPollInterval{20};

/// Runs work(control) on a thread of its own and waits for it with the GIL
/// released, polling every kPollInterval (with the GIL) for
///  - signals (PyErr_CheckSignals): a KeyboardInterrupt cancels the render,
///    waits for it to stop and is raised;
///  - `cancelEvent.is_set()` (a threading.Event or anything alike): cancels
///    (already set before the call: throws Error(Cancelled) at once);
///  - progress: `progress(fraction)` is called on the calling thread when the
///    fraction moved, and with 1.0 at the end of a successful call.
/// The library's exceptions are rethrown here (penumbra.Error); an exception
/// raised by `progress` cancels the render and is raised instead.
template <class Work>
auto runWaiting(Work&& work, const py::object& progress, const py::object& cancelEvent)
    -> decltype(work(std::declval<const pnb::RenderControl&>())) {
    using Result = decltype(work(std::declval<const pnb::RenderControl&>()));
    const bool hasProgress = !progress.is_none();
    const bool hasCancel = !cancelEvent.is_none();
    // Set before the call: nothing is rendered (a render shorter than one poll would otherwise finish).
    if (hasCancel && cancelEvent.attr("is_set")().cast<bool>())
        throw pnb::Error(pnb::ErrorCode::Cancelled, "render cancelled before it started: the cancel event is set");
    struct Shared {
        std::atomic<bool> cancel{false};
        std::atomic<double> fraction{0.0};
        std::mutex mutex;
        std::condition_variable cv;
        bool finished = false;
        std::exception_ptr error;
        std::optional<Result> result;
    } shared;

    pnb::RenderControl control;
    control.cancel = &shared.cancel;
    control.progress = [&shared](double f) { shared.fraction.store(f); };

    // Joins the render thread on every way out, cancelling it first unless it
    // finished; without the GIL, as nothing there needs it.
    struct Joiner {
        Shared& s;
        std::thread thread;
        ~Joiner() {
            if (!thread.joinable()) return;
            s.cancel.store(true);
            py::gil_scoped_release release;
            thread.join();
        }
    } joiner{shared, std::thread([&shared, &work, &control] {
                 try {
                     shared.result.emplace(work(control));
                 } catch (...) {
                     shared.error = std::current_exception();
                 }
                 std::lock_guard<std::mutex> lock(shared.mutex);
                 shared.finished = true;
                 shared.cv.notify_all();
             })};

    double reported = -1.0;
    for (bool finished = false; !finished;) {
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(shared.mutex);
            finished = shared.cv.wait_for(lock, kPollInterval, [&] { return shared.finished; });
        }
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Joiner cancels and joins
        if (finished) break;
        if (hasCancel && cancelEvent.attr("is_set")().cast<bool>()) shared.cancel.store(true);
        const double f = shared.fraction.load();
        if (hasProgress && f != reported && f < 1.0) {
            reported = f;
            progress(f);
        }
    }
    {
        py::gil_scoped_release release;
        joiner.thread.join();
    }
    if (shared.error) std::rethrow_exception(shared.error);
    if (hasProgress) progress(1.0);
    return std::move(*shared.result);
}

}  // namespace pnbpy
