// The preview's render loop and the state it shares with the server: a host of
// the public API whose passes add up to the one-shot image of the view shown,
// restarting from a camera move, stopping when asked.
#include "preview_render.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "orbit_camera.h"
#include "preview_state.h"

namespace penumbra::preview {
namespace {

pnb::Renderer quietRenderer() { return pnb::Renderer([](pnb::LogLevel, std::string_view) {}); }

pnb::PreparedScene litSphere(const pnb::Renderer& renderer) {
    pnb::Scene scene;
    pnb::Material red;
    red.kd = {0.7f, 0.2f, 0.1f};
    red.ks = pnb::gray(0.2f);
    red.exponent = 30.f;
    const pnb::MaterialId id = scene.addMaterial(red);
    scene.addPlane({0, 0, 0}, {0, 1, 0}, id);
    scene.addSphere({0, 0.6f, 0}, 0.6f, id);
    scene.addPointLight({2, 3, 3}, pnb::gray(15.f));
    return renderer.prepare(std::move(scene));
}

pnb::Camera sphereCamera() {
    pnb::Camera c;
    c.eye = {0.f, 1.4f, 4.5f};
    c.lookAt = {0.f, 0.6f, 0.f};
    return c;
}

pnb::RenderSettings smallSettings(int spp) {
    pnb::RenderSettings s;
    s.width = 24;
    s.height = 16;
    s.spp = spp;
    return s;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

nlohmann::json status(const PreviewState& state) { return nlohmann::json::parse(state.statusJson()); }

// A lit sphere, prepared, and a preview state started on it at `spp` samples per pixel.
struct SpherePreview {
    explicit SpherePreview(int spp) : settings(smallSettings(spp)) { state.start(settings, sphereCamera(), 0.f); }
    pnb::Renderer renderer = quietRenderer();
    pnb::PreparedScene scene = litSphere(renderer);
    pnb::RenderSettings settings;
    PreviewState state;
};

TEST(PreviewPasses, OneSampleFirstThenTheTargetTimeAtMostDoubling) {
    EXPECT_EQ(nextPassSamples(0, 64, 0, 0.0, 0.25), 1u);
    EXPECT_EQ(nextPassSamples(1, 64, 1, 0.001, 0.25), 2u);     // fast: doubles
    EXPECT_EQ(nextPassSamples(8, 64, 8, 1.0, 0.25), 2u);       // 8 per second: 2 in a quarter
    EXPECT_EQ(nextPassSamples(8, 64, 8, 1.0, 0.5), 4u);
    EXPECT_EQ(nextPassSamples(8, 64, 8, 100.0, 0.25), 1u);     // slow: one at a time
    EXPECT_EQ(nextPassSamples(60, 64, 32, 0.001, 0.25), 4u);   // never beyond spp
}

TEST(PreviewPasses, AQuarterSecondAtFirstGrowingToTwo) {
    EXPECT_EQ(passSeconds(0.0), 0.25);
    EXPECT_EQ(passSeconds(4.0), 0.5);
    EXPECT_EQ(passSeconds(600.0), 2.0);
}

TEST(PreviewState, LoadingRefusesMovesAndSaysSo) {
    PreviewState state("scene.obj");
    EXPECT_EQ(status(state)["phase"], "loading");
    EXPECT_EQ(status(state)["scene"], "scene.obj");
    EXPECT_EQ(status(state)["version"], 0);
    EXPECT_FALSE(state.image());
    try {
        state.moveCamera([](const pnb::Camera& c) { return c; });
        FAIL() << "a move while loading";
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), pnb::ErrorCode::InvalidScene);
    }
}

TEST(PreviewState, AMoveStartsANewViewAndCancelsThePassInFlight) {
    PreviewState state("sphere");
    state.start(smallSettings(4), sphereCamera(), 0.f);
    const PreviewState::View first = state.view();
    ASSERT_TRUE(state.beginPass(first.id));
    EXPECT_FALSE(state.cancelFlag()->load());
    state.moveCamera([](const pnb::Camera& c) { return orbit(c, 10.0, 0.0); });
    EXPECT_TRUE(state.cancelFlag()->load());
    EXPECT_FALSE(state.beginPass(first.id));
    const nlohmann::json j = status(state);
    EXPECT_EQ(j["phase"], "rendering");
    EXPECT_EQ(j["view"], first.id + 1);
    EXPECT_EQ(j["options"], cameraOptions(orbit(sphereCamera(), 10.0, 0.0)));
    // An invalid camera (the eye on the look-at point) is refused; the view stays.
    EXPECT_THROW(state.moveCamera([](const pnb::Camera& c) { return zoom(c, 0.0); }), pnb::Error);
    EXPECT_EQ(status(state)["view"], first.id + 1);
    state.resetCamera();
    EXPECT_EQ(status(state)["options"], cameraOptions(sphereCamera()));
}

TEST(PreviewState, ServesTheLatestPassEncodedOnceAsJpegThenTheFinalAsPng) {
    SpherePreview p(2);
    const PreviewState::View view = p.state.view();
    pnb::Framebuffer image(p.settings);
    const pnb::RenderStats stats = p.renderer.renderPass(p.scene, view.camera, p.settings, image, 0, 1);
    p.state.publish(view.id, image, stats);
    const auto first = p.state.image();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->version, 1u);
    EXPECT_EQ(first->view, view.id);
    EXPECT_EQ(*first->bytes, image.encodeImage("jpg"));
    EXPECT_STREQ(first->type, "image/jpeg");
    EXPECT_EQ(p.state.image()->bytes, first->bytes);  // the same bytes, not encoded again
    EXPECT_EQ(status(p.state)["image_samples"], 1);  // a page reads the status: the next pass is copied
    p.state.publish(view.id, image, stats);
    EXPECT_EQ(p.state.image()->version, 2u);
    p.state.publish(view.id, image, stats);  // no status read since: not copied
    EXPECT_EQ(p.state.image()->version, 2u);
    const pnb::RenderStats last = p.renderer.renderPass(p.scene, view.camera, p.settings, image, 1, 1);
    p.state.publish(view.id, image, last);
    EXPECT_EQ(p.state.image()->version, 3u);
    EXPECT_EQ(*p.state.image()->bytes, image.encodeImage("png"));
    EXPECT_STREQ(p.state.image()->type, "image/png");
    EXPECT_EQ(status(p.state)["image_samples"], 2);
    // A pass of a view no longer asked for is dropped.
    p.state.moveCamera([](const pnb::Camera& c) { return orbit(c, 5.0, 0.0); });
    p.state.publish(view.id, image, stats);
    EXPECT_EQ(p.state.image()->version, 3u);
}

// The loop run until a view completes: that view's image, camera and stats.
struct Completed {
    PreviewEnd end = PreviewEnd::Interrupted;
    int views = 0;
    std::vector<float> rgba;
    pnb::Camera camera;
    pnb::RenderStats stats;
};

Completed renderUntilComplete(SpherePreview& p) {
    std::atomic<bool> interrupted{false};
    Completed done;
    done.end = renderPreview({p.renderer, p.scene, p.settings}, p.state, interrupted, true,
                             [&](const pnb::Framebuffer& image, const pnb::Camera& camera, const pnb::RenderStats& stats) {
                                 done.rgba = image.rgba();
                                 done.camera = camera;
                                 done.stats = stats;
                                 ++done.views;
                             });
    return done;
}

TEST(PreviewRender, PassesGiveTheOneShotImageOfTheViewShown) {
    SpherePreview p(16);
    const Completed done = renderUntilComplete(p);
    EXPECT_EQ(done.end, PreviewEnd::Completed);
    EXPECT_EQ(done.views, 1);
    EXPECT_EQ(done.stats.samplesPerPixel, 16u);
    EXPECT_TRUE(sameBits(done.rgba, p.renderer.render(p.scene, sphereCamera(), p.settings).rgba()));
    EXPECT_EQ(status(p.state)["phase"], "complete");
}

TEST(PreviewRender, AMoveRestartsFromTheNewCamera) {
    SpherePreview p(1 << 20);  // never done: moved and stopped mid-way
    std::atomic<bool> interrupted{false};
    std::vector<pnb::Camera> completedCameras;
    std::thread mover([&] {
        while (status(p.state)["version"] == 0 && !interrupted.load())
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        p.state.moveCamera([](const pnb::Camera& c) { return orbit(c, 40.0, 10.0); });
        // Until a pass of the moved view is in, then stop (a minute at most: a machine under load).
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (status(p.state)["image_view"] != 2 && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        interrupted.store(true);
    });
    PreviewEnd end = PreviewEnd::Completed;
    EXPECT_NO_THROW(end = renderPreview({p.renderer, p.scene, p.settings}, p.state, interrupted, false,
                                        [&](const pnb::Framebuffer&, const pnb::Camera& c, const pnb::RenderStats&) {
                                            completedCameras.push_back(c);
                                        }));
    interrupted.store(true);
    mover.join();
    EXPECT_EQ(end, PreviewEnd::Interrupted);
    EXPECT_TRUE(completedCameras.empty());
    const nlohmann::json j = status(p.state);
    EXPECT_EQ(j["view"], 2);
    EXPECT_EQ(j["image_view"], 2) << "the moved view rendered passes before the interruption";
    EXPECT_EQ(j["phase"], "rendering");
}

TEST(PreviewRender, TheFinalImageIsTheOneShotImageOfTheMovedCamera) {
    SpherePreview p(64);
    // Moved before the render starts: the first view the loop renders is the moved one.
    p.state.moveCamera([](const pnb::Camera& c) { return pan(zoom(c, 0.8), 0.1, 0.05); });
    const pnb::Camera moved = pan(zoom(sphereCamera(), 0.8), 0.1, 0.05);
    const Completed done = renderUntilComplete(p);
    EXPECT_EQ(cameraOptions(done.camera), cameraOptions(moved));
    EXPECT_TRUE(sameBits(done.rgba, p.renderer.render(p.scene, moved, p.settings).rgba()));
}

}  // namespace
}  // namespace penumbra::preview
