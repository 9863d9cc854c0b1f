// Renderer::update: each kind of edit gives the same image, bit for bit, as
// preparing the edited scene from scratch, with both accelerators; the old
// prepared scene renders on unchanged; bad edits are errors naming the edit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <penumbra/penumbra.h>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "core/film.h"
#include "core/image_io.h"
#include "support/both_accelerators.h"
#include "support/test_support.h"

namespace {

pnb::Renderer quietRenderer() {
    return pnb::Renderer([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
}

// A lat-long image brighter toward +x, so that turning it changes the image.
std::string skyImage() {
    static const std::string path = [] {
        penumbra::Film film(16, 8, false);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 16; ++x) film.addRadiance(film.index(x, y), penumbra::Rgb(0.2f + 0.1f * x, 0.5f, 0.3f));
        film.setSampleCount(1);
        const auto file = penumbra::test::tempDir() / "edit_sky.pfm";
        penumbra::writeImage(file, film, penumbra::ImageWriteOptions{});
        return file.string();
    }();
    return path;
}

// What the tests change: everything an edit can reach.
struct Look {
    pnb::Matrix3x4 placements[3] = {pnb::Matrix3x4::translate({-1.5f, 0.8f, 0.f}),
                                    pnb::Matrix3x4::translate({0.f, 0.8f, 0.5f}) *
                                        pnb::Matrix3x4::rotate(30.f, {0, 1, 0}),
                                    pnb::Matrix3x4::translate({1.5f, 0.8f, -0.5f})};
    pnb::Color red{0.7f, 0.15f, 0.1f};
    pnb::Color lamp{5.f, 5.f, 5.f};
    pnb::Color point{8.f, 8.f, 8.f};
    pnb::Color sun{0.5f, 0.5f, 0.4f};
    float envRotate = 0.f, envScale = 0.5f;
};

pnb::Material redMaterial(const Look& look) {
    pnb::Material m;
    m.kd = look.red;
    m.ks = pnb::gray(0.2f);
    m.exponent = 20.f;
    return m;
}

pnb::Material lampMaterial(const Look& look) {
    pnb::Material m;
    m.kd = pnb::gray(0.f);
    m.ke = look.lamp;
    return m;
}

// A floor, a sphere, a world mesh, a lamp, point and directional lights, an
// image environment, and three instances of a box-shaped prototype.
pnb::Scene scene(const Look& look) {
    pnb::Scene s;
    pnb::Material white;
    white.kd = pnb::gray(0.6f);
    const auto w = s.addMaterial(white), r = s.addMaterial(redMaterial(look)), l = s.addMaterial(lampMaterial(look));
    s.addPlane({0, 0, 0}, {0, 1, 0}, w);
    s.addSphere({-0.5f, 0.4f, 1.5f}, 0.4f, w);
    s.addRectangle({-1, 3, -1}, {2, 0, 0}, {0, 0, 2}, l);
    s.addMesh({-2.5f, 0, -2, -1.5f, 0, -2, -2, 1.5f, -2}, {0, 1, 2}, r);
    s.addPointLight({2, 4, 3}, look.point);
    s.addDirectionalLight({-0.3f, -1.f, -0.2f}, look.sun);
    s.setEnvironmentImage(skyImage(), look.envRotate, look.envScale);
    const pnb::PrototypeId p = s.addPrototype("box");
    const std::vector<float> pos = {-.5f, -.5f, -.5f, .5f, -.5f, -.5f, .5f, .5f, -.5f, -.5f, .5f, -.5f,
                                    -.5f, -.5f, .5f,  .5f, -.5f, .5f,  .5f, .5f, .5f,  -.5f, .5f, .5f};
    const std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                       3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    pnb::MeshDesc d;
    d.positions = pos.data();
    d.vertexCount = pos.size() / 3;
    d.indices = idx.data();
    d.triangleCount = idx.size() / 3;
    d.material = r;
    s.addPrototypeMesh(p, d);
    for (const auto& m : look.placements) s.addInstance(p, m);
    return s;
}

constexpr pnb::MaterialId kRed = 1, kLamp = 2;

pnb::RenderSettings settings() {
    pnb::RenderSettings st;
    st.width = 40;  // small: the naive loop tests every primitive for every ray
    st.height = 30;
    st.spp = 2;
    st.lightSamples = 2;
    st.seed = 5;
    st.integrator = pnb::IntegratorKind::Path;
    st.maxDepth = 3;
    return st;
}

pnb::Camera camera() {
    pnb::Camera c;
    c.eye = {0.5f, 3.f, 6.f};
    c.lookAt = {0, 0.5f, 0};
    c.vfovDegrees = 45.f;
    return c;
}

std::vector<float> render(const pnb::Renderer& r, const pnb::PreparedScene& p) {
    return r.render(p, camera(), settings()).rgba();
}

class SceneEdit : public penumbra::test::ForBothAccelerators {
protected:
    // Updates the prepared `before` by `edits`, prepares `after` from scratch,
    // and expects the same image; `before` must render as it did.
    void expectSameAsFresh(const Look& before, const pnb::SceneEdits& edits, const Look& after) {
        const pnb::Renderer r = quietRenderer();
        const pnb::PrepareOptions opt{GetParam()};
        const pnb::PreparedScene base = r.prepare(scene(before), opt);
        const std::vector<float> baseImage = render(r, base);
        const pnb::PreparedScene edited = r.update(base, edits);
        const std::vector<float> fresh = render(r, r.prepare(scene(after), opt));
        const std::vector<float> image = render(r, edited);
        EXPECT_NE(image, baseImage) << "the edit changed nothing";
        EXPECT_EQ(image, fresh);
        EXPECT_EQ(render(r, base), baseImage);
        EXPECT_EQ(edited.lightCount(), r.prepare(scene(after), opt).lightCount());
    }
};

TEST_P(SceneEdit, MovingInstancesMatchesAFreshPrepare) {
    Look after;
    after.placements[1] = pnb::Matrix3x4::translate({0.3f, 1.2f, 0.f}) * pnb::Matrix3x4::scale({1.5f, 0.5f, 1.f});
    after.placements[2] = pnb::Matrix3x4::translate({1.2f, 0.5f, 1.f});
    pnb::SceneEdits e;
    e.transforms = {{1, after.placements[1]}, {2, after.placements[2]}};
    expectSameAsFresh(Look{}, e, after);
}

TEST_P(SceneEdit, ChangingAMaterialMatchesAFreshPrepare) {
    Look after;
    after.red = {0.1f, 0.3f, 0.8f};
    pnb::SceneEdits e;
    e.materials = {{kRed, redMaterial(after)}};
    expectSameAsFresh(Look{}, e, after);
}

TEST_P(SceneEdit, ChangingLightsMatchesAFreshPrepare) {
    Look after;
    after.lamp = {9.f, 6.f, 2.f};
    after.point = {2.f, 3.f, 12.f};
    after.sun = {1.5f, 0.2f, 0.2f};
    pnb::SceneEdits e;
    e.materials = {{kLamp, lampMaterial(after)}};
    e.pointLights = {{0, after.point}};
    e.directionalLights = {{0, after.sun}};
    expectSameAsFresh(Look{}, e, after);
}

TEST_P(SceneEdit, TurningOffTheLampMatchesAFreshPrepare) {
    Look after;
    after.lamp = {0.f, 0.f, 0.f};  // no longer an area light: the light set is rebuilt without it
    pnb::SceneEdits e;
    e.materials = {{kLamp, lampMaterial(after)}};
    expectSameAsFresh(Look{}, e, after);
}

TEST_P(SceneEdit, TurningAndScalingTheEnvironmentMatchesAFreshPrepare) {
    Look after;
    after.envRotate = 120.f;
    after.envScale = 2.f;
    pnb::SceneEdits e;
    e.environmentRotateDegrees = after.envRotate;
    e.environmentScale = after.envScale;
    expectSameAsFresh(Look{}, e, after);
}

TEST_P(SceneEdit, EditsOfAnEditMatchAFreshPrepare) {
    const pnb::Renderer r = quietRenderer();
    const pnb::PrepareOptions opt{GetParam()};
    Look after;
    after.placements[0] = pnb::Matrix3x4::translate({-1.f, 1.5f, 1.f});
    after.red = {0.9f, 0.9f, 0.1f};
    pnb::SceneEdits move, paint;
    move.transforms = {{0, after.placements[0]}};
    paint.materials = {{kRed, redMaterial(after)}};
    const pnb::PreparedScene edited = r.update(r.update(r.prepare(scene(Look{}), opt), move), paint);
    EXPECT_EQ(render(r, edited), render(r, r.prepare(scene(after), opt)));
}

TEST_P(SceneEdit, BadEditsAreErrorsAndTheSceneStaysUsable) {
    const pnb::Renderer r = quietRenderer();
    const pnb::PreparedScene base = r.prepare(scene(Look{}), pnb::PrepareOptions{GetParam()});
    const std::vector<float> image = render(r, base);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    auto expectError = [&](const pnb::SceneEdits& e, const std::string& words) {
        try {
            (void)r.update(base, e);
            ADD_FAILURE() << "no error for an edit of " << words;
        } catch (const pnb::Error& err) {
            EXPECT_EQ(err.code(), pnb::ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(err.what()).find(words), std::string::npos) << err.what();
        }
    };
    pnb::SceneEdits e;
    e.transforms = {{3, pnb::Matrix3x4{}}};
    expectError(e, "instance 3");
    e.transforms = {{0, pnb::Matrix3x4::scale({1.f, 0.f, 1.f})}};
    expectError(e, "finite and invertible");
    pnb::Matrix3x4 m;
    m.m[1][3] = nan;
    e.transforms = {{0, m}};
    expectError(e, "finite and invertible");
    e = {};
    e.materials = {{7, pnb::Material{}}};
    expectError(e, "material 7");
    pnb::Material glowing = redMaterial(Look{});
    glowing.ke = {1.f, 1.f, 1.f};  // its prototype's instances would become meshes
    e.materials = {{kRed, glowing}};
    expectError(e, "prepare the edited scene");
    pnb::Material bad;
    bad.kd = {nan, 0.f, 0.f};
    e.materials = {{kRed, bad}};
    expectError(e, "kd");
    e = {};
    e.pointLights = {{0, {nan, 1.f, 1.f}}};
    expectError(e, "point light 0");
    e.pointLights = {{4, {1.f, 1.f, 1.f}}};
    expectError(e, "point light 4");
    e = {};
    e.directionalLights = {{0, {-1.f, 1.f, 1.f}}};
    expectError(e, "directional light 0");
    e = {};
    e.environmentScale = nan;
    expectError(e, "environment scale");
    EXPECT_EQ(render(r, base), image);
}

// The old scene is immutable and shared: renders of it running on another
// thread while edits are made (and the old handle dropped) give the image
// they give alone, and the edited scene outlives the one it came from.
TEST_P(SceneEdit, EditsLeaveRendersOfTheOldSceneUndisturbed) {
    const pnb::Renderer r = quietRenderer();
    const pnb::PrepareOptions opt{GetParam()};
    pnb::PreparedScene base = r.prepare(scene(Look{}), opt);
    pnb::RenderSettings longer = settings();
    longer.spp = 32;  // still running while the edits are made
    const std::vector<float> alone = r.render(base, camera(), longer).rgba();
    pnb::RenderJob job = r.renderAsync(base, camera(), longer);
    Look after;
    after.placements[0] = pnb::Matrix3x4::translate({-1.f, 1.5f, 1.f});
    pnb::SceneEdits e;
    e.transforms = {{0, after.placements[0]}};
    std::vector<pnb::PreparedScene> edits;
    for (int i = 0; i < 8; ++i) edits.push_back(r.update(i ? edits.back() : base, e));
    base = pnb::PreparedScene{};  // the job and the edits keep what they use alive
    job.wait();
    EXPECT_EQ(job.framebuffer().rgba(), alone);
    EXPECT_EQ(render(r, edits.back()), render(r, r.prepare(scene(after), opt)));
}

PENUMBRA_FOR_BOTH_ACCELERATORS(SceneEdit);

TEST(SceneEditApi, AddInstanceReturnsItsIndex) {
    pnb::Scene s;
    const pnb::PrototypeId p = s.addPrototype("empty");
    EXPECT_EQ(s.addInstance(p, pnb::Matrix3x4{}), 0u);
    EXPECT_EQ(s.addInstance(p, pnb::Matrix3x4::translate({1, 0, 0})), 1u);
}

TEST(SceneEditApi, AnEnvironmentEditNeedsAnEnvironment) {
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s;
    s.addSphere({0, 0, 0}, 1.f, 0);
    s.addPointLight({0, 3, 0}, pnb::gray(1.f));
    pnb::SceneEdits e;
    e.environmentRotateDegrees = 10.f;
    EXPECT_THROW((void)r.update(r.prepare(s), e), pnb::Error);
    EXPECT_THROW((void)r.update(pnb::PreparedScene{}, e), pnb::Error);
}

// The C API: a scene of two instanced triangles; moving one by pnb_update
// renders as preparing the moved scene; a bad index is an error.
pnb_prepared_scene* preparedTriangles(pnb_renderer* r, float secondX) {
    pnb_scene* s = nullptr;
    EXPECT_EQ(pnb_scene_create(&s), PNB_OK);
    pnb_material m;
    pnb_material_init(&m);
    uint32_t mat = 0, proto = 0;
    EXPECT_EQ(pnb_scene_add_material(s, &m, &mat), PNB_OK);
    EXPECT_EQ(pnb_scene_add_plane(s, pnb_vec3{0, -1, 0}, pnb_vec3{0, 1, 0}, 1, mat), PNB_OK);
    EXPECT_EQ(pnb_scene_add_point_light(s, pnb_vec3{0, 3, 3}, pnb_color{5, 5, 5}), PNB_OK);
    EXPECT_EQ(pnb_scene_add_prototype(s, "tri", &proto), PNB_OK);
    const float pos[] = {-1, 0, 0, 1, 0, 0, 0, 1.5f, 0};
    const uint32_t idx[] = {0, 1, 2};
    pnb_mesh_desc d;
    pnb_mesh_desc_init(&d);
    d.positions = pos;
    d.vertex_count = 3;
    d.indices = idx;
    d.triangle_count = 1;
    d.material = mat;
    EXPECT_EQ(pnb_scene_add_prototype_mesh(s, proto, &d), PNB_OK);
    const float first[12] = {1, 0, 0, -1.5f, 0, 1, 0, 0, 0, 0, 1, 0};
    const float second[12] = {1, 0, 0, secondX, 0, 1, 0, 0, 0, 0, 1, 0};
    EXPECT_EQ(pnb_scene_add_instance(s, proto, first, PNB_KEEP_MATERIALS), PNB_OK);
    EXPECT_EQ(pnb_scene_add_instance(s, proto, second, PNB_KEEP_MATERIALS), PNB_OK);
    pnb_prepared_scene* p = nullptr;
    EXPECT_EQ(pnb_prepare(r, s, nullptr, &p), PNB_OK);
    pnb_scene_destroy(s);
    return p;
}

std::vector<float> renderC(pnb_renderer* r, const pnb_prepared_scene* p) {
    pnb_camera c;
    pnb_camera_init(&c);
    c.eye = pnb_vec3{0, 0.5f, 5};
    c.look_at = pnb_vec3{0, 0.5f, 0};
    pnb_render_settings st;
    pnb_render_settings_init(&st);
    st.width = 24;
    st.height = 16;
    st.spp = 1;
    std::vector<float> rgba(24 * 16 * 4);
    EXPECT_EQ(pnb_render_rgba(r, p, &c, &st, rgba.data(), rgba.size(), nullptr, nullptr), PNB_OK);
    return rgba;
}

TEST(SceneEditCApi, MovingAnInstanceMatchesAFreshPrepare) {
    pnb_renderer* r = nullptr;
    ASSERT_EQ(pnb_renderer_create(&r), PNB_OK);
    pnb_prepared_scene* base = preparedTriangles(r, 1.5f);
    pnb_prepared_scene* fresh = preparedTriangles(r, 0.5f);
    const std::vector<float> before = renderC(r, base);
    pnb_transform_edit move{1, {1, 0, 0, 0.5f, 0, 1, 0, 0, 0, 0, 1, 0}};
    pnb_scene_edits e;
    pnb_scene_edits_init(&e);
    e.transforms = &move;
    e.transform_count = 1;
    pnb_prepared_scene* edited = nullptr;
    ASSERT_EQ(pnb_update(r, base, &e, &edited), PNB_OK);
    EXPECT_EQ(renderC(r, edited), renderC(r, fresh));
    EXPECT_NE(renderC(r, edited), before);

    move.instance = 2;
    pnb_prepared_scene* none = nullptr;
    EXPECT_EQ(pnb_update(r, base, &e, &none), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(none, nullptr);
    EXPECT_NE(std::string(pnb_renderer_last_error(r)).find("instance 2"), std::string::npos)
        << pnb_renderer_last_error(r);
    e.transform_count = 2;
    e.transforms = nullptr;
    EXPECT_EQ(pnb_update(r, base, &e, &none), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(renderC(r, base), before);
    pnb_prepared_scene_destroy(edited);
    pnb_prepared_scene_destroy(fresh);
    pnb_prepared_scene_destroy(base);
    pnb_renderer_destroy(r);
}

}  // namespace
