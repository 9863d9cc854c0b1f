// The C API: status codes and last-error messages for bad input (NULL handles,
// bad files, bad settings), rendering, passes, callbacks and jobs. Compiled as
// C++ here, which also checks that penumbra.h is usable from C++.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <iterator>
#include <penumbra/penumbra.h>
#include <penumbra/penumbra.hpp>
#include <string>
#include <thread>
#include <vector>

#include "support/test_support.h"

namespace {

std::string lastError() { return pnb_last_error(); }

// Stores an int a C host might put in an enum field (a static_cast to an
// out-of-range enum value would be undefined behaviour in C++).
template <class E>
void setRaw(E& field, int value) {
    static_assert(sizeof(E) == sizeof(int));
    std::memcpy(&field, &value, sizeof value);
}

pnb_vec3 v3(float x, float y, float z) { return pnb_vec3{x, y, z}; }
pnb_color gray(float g) { return pnb_color{g, g, g}; }

void quiet(pnb_log_level, const char*, void*) {}

// Owns the handles of one test; destroys them in order.
struct Fixture {
    pnb_renderer* renderer = nullptr;
    pnb_scene* scene = nullptr;
    pnb_prepared_scene* prepared = nullptr;
    pnb_framebuffer* image = nullptr;
    pnb_camera camera{};
    pnb_render_settings settings{};

    Fixture() {
        EXPECT_EQ(pnb_renderer_create(&renderer), PNB_OK);
        EXPECT_EQ(pnb_renderer_set_log(renderer, quiet, nullptr, PNB_LOG_ERROR), PNB_OK);
        EXPECT_EQ(pnb_scene_create(&scene), PNB_OK);
        pnb_camera_init(&camera);
        camera.eye = v3(0, 0, 4);
        camera.look_at = v3(0, 0, 0);
        pnb_render_settings_init(&settings);
        settings.width = 33;
        settings.height = 33;
        settings.spp = 8;
        settings.seed = 3;
    }
    ~Fixture() {
        pnb_framebuffer_destroy(image);
        pnb_prepared_scene_destroy(prepared);
        pnb_scene_destroy(scene);
        pnb_renderer_destroy(renderer);
    }
    // A white sphere lit head-on by a point light, on a mirror-and-area-light stage.
    void buildSphere() {
        pnb_material white, lamp;
        pnb_material_init(&white);
        white.kd = gray(0.8f);
        pnb_material_init(&lamp);
        lamp.kd = gray(0.f);
        lamp.ke = gray(4.f);
        uint32_t w = 99, l = 99;
        ASSERT_EQ(pnb_scene_add_material(scene, &white, &w), PNB_OK);
        ASSERT_EQ(pnb_scene_add_material(scene, &lamp, &l), PNB_OK);
        EXPECT_EQ(w, 0u);
        EXPECT_EQ(l, 1u);
        ASSERT_EQ(pnb_scene_add_sphere(scene, v3(0, 0, 0), 1.f, w), PNB_OK);
        ASSERT_EQ(pnb_scene_add_point_light(scene, v3(0, 0, 5), gray(20.f)), PNB_OK);
        ASSERT_EQ(pnb_scene_add_disk(scene, v3(0, 3, 0), v3(0, -1, 0), 0.5f, l), PNB_OK);
        ASSERT_EQ(pnb_scene_add_plane(scene, v3(0, -1, 0), v3(0, 1, 0), 1, w), PNB_OK);
        const float rotate[12] = {0.8f, 0, 0.6f, 1.5f, 0, 1, 0, -0.5f, -0.6f, 0, 0.8f, 0};
        ASSERT_EQ(pnb_scene_add_box(scene, v3(-0.2f, -0.5f, -0.2f), v3(0.2f, 0.5f, 0.2f), rotate, w), PNB_OK);
        ASSERT_EQ(pnb_scene_add_rectangle(scene, v3(-2, -1, -2), v3(4, 0, 0), v3(0, 3, 0), w), PNB_OK);
        ASSERT_EQ(pnb_scene_add_directional_light(scene, v3(0, -1, -1), gray(0.2f)), PNB_OK);
        ASSERT_EQ(pnb_scene_set_ambient(scene, gray(0.02f)), PNB_OK);
        ASSERT_EQ(pnb_scene_set_background(scene, pnb_color{0.1f, 0.2f, 0.3f}), PNB_OK);
    }
    void prepare() { ASSERT_EQ(pnb_prepare(renderer, scene, nullptr, &prepared), PNB_OK) << lastError(); }
    std::vector<float> read(const pnb_framebuffer* fb) {
        std::vector<float> px(size_t(pnb_framebuffer_width(fb)) * size_t(pnb_framebuffer_height(fb)) * 4);
        EXPECT_EQ(pnb_framebuffer_read_rgba(fb, px.data(), px.size()), PNB_OK);
        return px;
    }
};

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// ---------------------------------------------------------------- bad input

TEST(CApi, NullHandlesAndArgumentsAreErrorsNotCrashes) {
    pnb_scene* scene = reinterpret_cast<pnb_scene*>(0x1);  // must be reset to NULL
    EXPECT_EQ(pnb_scene_load(nullptr, "x.json", nullptr, &scene), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(scene, nullptr);
    EXPECT_EQ(lastError(), "pnb_scene_load: renderer is NULL");

    EXPECT_EQ(pnb_scene_add_sphere(nullptr, v3(0, 0, 0), 1.f, 0), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(lastError(), "pnb_scene_add_sphere: scene is NULL");
    EXPECT_EQ(pnb_prepare(nullptr, nullptr, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(lastError(), "pnb_prepare: renderer is NULL");
    EXPECT_EQ(pnb_render(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_framebuffer_read_rgba(nullptr, nullptr, 0), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(lastError(), "pnb_framebuffer_read_rgba: framebuffer is NULL");
    EXPECT_EQ(pnb_framebuffer_write_image(nullptr, "x.png", nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_render_job_wait(nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_render_job_cancel(nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_render_settings_validate(nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_renderer_create(nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(lastError(), "pnb_renderer_create: out is NULL");
    EXPECT_EQ(pnb_render_job_progress(nullptr), 0.0);
    EXPECT_EQ(pnb_render_job_done(nullptr), 0);
    EXPECT_EQ(pnb_framebuffer_width(nullptr), 0);
    EXPECT_EQ(pnb_scene_primitive_count(nullptr), 0u);
    EXPECT_STREQ(pnb_scene_last_error(nullptr), "");
    pnb_renderer_destroy(nullptr);
    pnb_scene_destroy(nullptr);
    pnb_prepared_scene_destroy(nullptr);
    pnb_framebuffer_destroy(nullptr);
    pnb_render_job_destroy(nullptr);

    Fixture f;
    EXPECT_EQ(pnb_scene_add_material(f.scene, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_scene_last_error(f.scene), std::string("pnb_scene_add_material: material is NULL"));
    EXPECT_EQ(pnb_scene_add_mesh(f.scene, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_render(f.renderer, nullptr, &f.camera, &f.settings, nullptr, nullptr, nullptr),
              PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(pnb_renderer_last_error(f.renderer), "pnb_render: prepared scene is NULL");
}

TEST(CApi, BadScenesAndFilesNameTheProblem) {
    Fixture f;
    EXPECT_EQ(pnb_scene_add_sphere(f.scene, v3(0, 0, 0), 1.f, 7), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pnb_scene_last_error(f.scene)).find("material id 7 does not exist"), std::string::npos);
    EXPECT_EQ(pnb_scene_add_disk(f.scene, v3(0, 0, 0), v3(0, 1, 0), 0.f, 0), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("disk radius"), std::string::npos) << lastError();
    pnb_material m;
    pnb_material_init(&m);
    EXPECT_EQ(m.ior, pnb::Material{}.ior);  // glass fields come from the C++ defaults
    EXPECT_EQ(m.kt.r, 0.f);
    m.ior = 0.f;
    EXPECT_EQ(pnb_scene_add_material(f.scene, &m, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("ior must be finite and > 0"), std::string::npos) << lastError();
    pnb_material_init(&m);
    setRaw(m.model, 5);
    EXPECT_EQ(pnb_scene_add_material(f.scene, &m, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("is not a pnb_phong_model"), std::string::npos) << lastError();
    pnb_mesh_desc mesh;
    pnb_mesh_desc_init(&mesh);
    EXPECT_EQ(pnb_scene_add_mesh(f.scene, &mesh), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("needs at least one vertex and one triangle"), std::string::npos) << lastError();

    const auto dir = penumbra::test::tempDir();
    pnb_scene* loaded = nullptr;
    const std::string missing = (dir / "missing.json").string();
    EXPECT_EQ(pnb_scene_load(f.renderer, missing.c_str(), nullptr, &loaded), PNB_ERROR_FILE_NOT_FOUND);
    EXPECT_EQ(loaded, nullptr);
    EXPECT_NE(std::string(pnb_renderer_last_error(f.renderer)).find("missing.json"), std::string::npos);
    const std::string bad = penumbra::test::writeFile(dir / "bad.json", "{ \"camera\": { \"fov\": 500 } }").string();
    EXPECT_EQ(pnb_scene_load(f.renderer, bad.c_str(), nullptr, &loaded), PNB_ERROR_INVALID_SCENE);
    EXPECT_NE(lastError().find("bad.json: /camera/fov"), std::string::npos) << lastError();
    const std::string broken = penumbra::test::writeFile(dir / "broken.obj", "v 0 0 0\nf 1 2 x\n").string();
    pnb_load_options strict;
    pnb_load_options_init(&strict);
    strict.strict = 1;
    EXPECT_EQ(pnb_scene_load(f.renderer, broken.c_str(), &strict, &loaded), PNB_ERROR_PARSE);
    EXPECT_NE(lastError().find("broken.obj: 1 face(s) with invalid vertex indices"), std::string::npos) << lastError();
    EXPECT_NE(lastError().find("line 2"), std::string::npos) << lastError();
}

TEST(CApi, BadSettingsAreRejectedBeforeAnyWork) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    pnb_render_settings s = f.settings;
    s.width = -4;
    pnb_framebuffer* image = reinterpret_cast<pnb_framebuffer*>(0x1);
    EXPECT_EQ(pnb_framebuffer_create(&s, &image), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(image, nullptr);
    EXPECT_EQ(lastError(), "pnb_framebuffer_create: width must be in [1, 65536], got -4");
    EXPECT_EQ(pnb_render_settings_validate(&s), PNB_ERROR_INVALID_ARGUMENT);

    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    s = f.settings;
    s.spp = 0;
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &s, f.image, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pnb_renderer_last_error(f.renderer)).find("spp"), std::string::npos);
    s = f.settings;
    setRaw(s.light_selection, 7);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &s, f.image, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("light_selection 7"), std::string::npos) << lastError();
    pnb_render_settings_init(&s);
    EXPECT_EQ(s.light_selection, PNB_LIGHTS_AUTO);
    s = f.settings;
    EXPECT_EQ(s.integrator, PNB_INTEGRATOR_WHITTED);
    setRaw(s.integrator, 9);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &s, f.image, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("integrator 9 is not a pnb_integrator"), std::string::npos) << lastError();
    s = f.settings;
    EXPECT_EQ(s.direct_light, PNB_DIRECT_LIGHT_MIS);
    setRaw(s.direct_light, 3);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &s, f.image, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("direct_light 3"), std::string::npos) << lastError();
    pnb_camera cam = f.camera;
    cam.vfov_degrees = 0.f;
    EXPECT_EQ(pnb_camera_validate(&cam), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &cam, &f.settings, f.image, nullptr, nullptr),
              PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_framebuffer_sample_count(f.image), 0u);

    s = f.settings;
    s.width = s.height = 65536;
    EXPECT_EQ(pnb_framebuffer_create(&s, &image), PNB_ERROR_OUT_OF_MEMORY);
    EXPECT_NE(lastError().find("framebuffer needs"), std::string::npos) << lastError();

    pnb_prepare_options po;
    pnb_prepare_options_init(&po);
    setRaw(po.accelerator, 5);
    pnb_prepared_scene* p = nullptr;
    EXPECT_EQ(pnb_prepare(f.renderer, f.scene, &po, &p), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("accelerator 5 is not an AcceleratorKind"), std::string::npos) << lastError();
    pnb_prepare_options badQuality;
    pnb_prepare_options_init(&badQuality);
    setRaw(badQuality.quality, 3);
    EXPECT_EQ(pnb_prepare(f.renderer, f.scene, &badQuality, &p), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("build quality 3 is not a pnb_build_quality"), std::string::npos) << lastError();
}

// ---------------------------------------------------------------- rendering

TEST(CApi, RendersTheExpectedRadianceAndWritesImages) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    pnb_prepared_info info;
    ASSERT_EQ(pnb_prepared_scene_get_info(f.prepared, &info), PNB_OK);
    EXPECT_EQ(info.primitive_count, 5u);  // sphere, disk, plane, box, rectangle
    EXPECT_EQ(info.light_count, 3u);  // point, directional, emissive disk
    EXPECT_EQ(pnb_scene_primitive_count(f.scene), 5u);  // the scene stays usable

    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    pnb_render_stats stats;
    ASSERT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, nullptr, &stats), PNB_OK)
        << lastError();
    EXPECT_EQ(stats.samples_per_pixel, 8u);
    EXPECT_GT(stats.camera_rays, 0u);
    pnb_color c;
    ASSERT_EQ(pnb_framebuffer_pixel(f.image, 16, 16, &c), PNB_OK);
    const float pointLight = 0.8f / 3.14159265f * 20.f / 16.f;
    EXPECT_GT(c.r, pointLight);          // plus ambient, the disk and the directional light
    EXPECT_LT(c.r, pointLight + 0.05f);
    EXPECT_EQ(pnb_framebuffer_pixel(f.image, 33, 0, &c), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pnb_framebuffer_last_error(f.image)).find("outside the 33x33 framebuffer"),
              std::string::npos);

    std::vector<float> small(10);
    EXPECT_EQ(pnb_framebuffer_read_rgba(f.image, small.data(), small.size()), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("needs 4356"), std::string::npos) << lastError();
    std::vector<float> host(33 * 33 * 4);
    ASSERT_EQ(pnb_render_rgba(f.renderer, f.prepared, &f.camera, &f.settings, host.data(), host.size(), nullptr,
                              nullptr),
              PNB_OK);
    EXPECT_TRUE(sameBits(host, f.read(f.image)));

    const auto dir = penumbra::test::tempDir();
    const std::string png = (dir / "c.png").string();
    ASSERT_EQ(pnb_framebuffer_write_image(f.image, png.c_str(), nullptr), PNB_OK);
    EXPECT_GT(std::filesystem::file_size(png), 0u);
    const std::string nowhere = (dir / "no" / "c.png").string();
    EXPECT_EQ(pnb_framebuffer_write_image(f.image, nowhere.c_str(), nullptr), PNB_ERROR_IO);
    EXPECT_NE(lastError().find(nowhere), std::string::npos) << lastError();
    // In memory: the same bytes as the file, in a buffer the host frees.
    uint8_t* data = nullptr;
    size_t size = 0;
    ASSERT_EQ(pnb_framebuffer_encode_image(f.image, "png", nullptr, &data, &size), PNB_OK);
    std::ifstream written(png, std::ios::binary);
    const std::string file((std::istreambuf_iterator<char>(written)), {});
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(data), size), file);
    pnb_bytes_free(data);
    pnb_bytes_free(nullptr);
    EXPECT_EQ(pnb_framebuffer_encode_image(f.image, "gif", nullptr, &data, &size), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(data, nullptr);
    EXPECT_EQ(size, 0u);
    EXPECT_NE(std::string(pnb_framebuffer_last_error(f.image)).find("unknown image format 'gif'"), std::string::npos);
    EXPECT_EQ(pnb_framebuffer_encode_image(f.image, "png", nullptr, nullptr, &size), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_framebuffer_encode_image(nullptr, "png", nullptr, &data, &size), PNB_ERROR_INVALID_ARGUMENT);
}

namespace {

// A quad (with normals and uvs) of material `m`, lit head-on by a point
// light, rendered through the C API into f and through the C++ API with `cm`;
// returns the C++ image after checking that both are the same bits.
std::vector<float> expectQuadSameThroughBothApis(Fixture& f, const pnb_material& m, const pnb::Material& cm) {
    uint32_t id = 0;
    EXPECT_EQ(pnb_scene_add_material(f.scene, &m, &id), PNB_OK) << pnb_scene_last_error(f.scene);
    static const float pos[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    static const float nrm[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    static const float uvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    pnb_mesh_desc mesh;
    pnb_mesh_desc_init(&mesh);
    mesh.name = "quad";
    mesh.positions = pos;
    mesh.vertex_count = 4;
    mesh.indices = idx;
    mesh.triangle_count = 2;
    mesh.normals = nrm;
    mesh.uvs = uvs;
    mesh.material = id;
    EXPECT_EQ(pnb_scene_add_mesh(f.scene, &mesh), PNB_OK) << pnb_scene_last_error(f.scene);
    EXPECT_EQ(pnb_scene_add_point_light(f.scene, v3(0.5f, 0.5f, 3), gray(10.f)), PNB_OK);
    f.prepare();
    EXPECT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, nullptr, nullptr), PNB_OK);

    pnb::Scene s;
    pnb::MeshDesc cmesh;
    cmesh.material = s.addMaterial(cm);
    cmesh.positions = pos;
    cmesh.vertexCount = 4;
    cmesh.indices = idx;
    cmesh.triangleCount = 2;
    cmesh.normals = nrm;
    cmesh.uvs = uvs;
    s.addMesh(cmesh);
    s.addPointLight({0.5f, 0.5f, 3}, pnb::gray(10.f));
    pnb::RenderSettings st;
    st.width = st.height = 33;
    st.spp = 8;
    st.seed = 3;
    pnb::Camera cam;
    cam.eye = {0, 0, 4};
    cam.lookAt = {0, 0, 0};
    const pnb::Renderer r([](pnb::LogLevel, std::string_view) {});
    std::vector<float> cpp = r.render(r.prepare(s), cam, st).rgba();
    EXPECT_TRUE(sameBits(f.read(f.image), cpp));
    return cpp;
}

}  // namespace

TEST(CApi, SameImageAsTheCppApi) {
    Fixture f;
    pnb_material m;
    pnb_material_init(&m);
    m.kd = pnb_color{0.6f, 0.3f, 0.2f};
    m.ks = gray(0.3f);
    m.exponent = 20.f;
    pnb::Material cm;
    cm.kd = {0.6f, 0.3f, 0.2f};
    cm.ks = pnb::gray(0.3f);
    cm.exponent = 20.f;
    expectQuadSameThroughBothApis(f, m, cm);
}

TEST(CApi, PassesConvergeToTheOneShotImage) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    f.settings.spp = 10;
    f.settings.aovs = 1;
    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    ASSERT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, nullptr, nullptr), PNB_OK);
    pnb_framebuffer* passes = nullptr;
    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &passes), PNB_OK);
    for (uint32_t first = 0; first < 10; first += 4) {
        const uint32_t count = first + 4 <= 10 ? 4 : 10 - first;
        ASSERT_EQ(pnb_render_pass(f.renderer, f.prepared, &f.camera, &f.settings, passes, first, count, nullptr,
                                  nullptr),
                  PNB_OK)
            << lastError();
        EXPECT_EQ(pnb_framebuffer_sample_count(passes), first + count);
    }
    EXPECT_TRUE(sameBits(f.read(passes), f.read(f.image)));
    std::vector<float> d1(33 * 33), d2(33 * 33);
    ASSERT_EQ(pnb_framebuffer_read_depth(passes, d1.data(), d1.size()), PNB_OK);
    ASSERT_EQ(pnb_framebuffer_read_depth(f.image, d2.data(), d2.size()), PNB_OK);
    EXPECT_TRUE(sameBits(d1, d2));
    EXPECT_NEAR(d1[16 * 33 + 16], 3.f, 0.01f);
    // A pass that does not continue where the framebuffer stands is refused.
    EXPECT_EQ(pnb_render_pass(f.renderer, f.prepared, &f.camera, &f.settings, passes, 0, 1, nullptr, nullptr),
              PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("holds 10 samples"), std::string::npos) << lastError();
    EXPECT_EQ(pnb_framebuffer_clear(passes), PNB_OK);
    EXPECT_EQ(pnb_framebuffer_sample_count(passes), 0u);
    pnb_framebuffer_destroy(passes);
}

struct ProgressLog {
    std::vector<double> values;
    int cancelAt = -1;  // index of the call that asks to cancel
};

int recordProgress(double fraction, void* user) {
    auto* log = static_cast<ProgressLog*>(user);
    log->values.push_back(fraction);
    return int(log->values.size()) - 1 == log->cancelAt ? 1 : 0;
}

TEST(CApi, ProgressReachesOneAndCanCancel) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    ProgressLog log;
    pnb_render_callbacks cb;
    pnb_render_callbacks_init(&cb);
    cb.progress = recordProgress;
    cb.user = &log;
    ASSERT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, &cb, nullptr), PNB_OK);
    ASSERT_EQ(log.values.size(), 9u);  // 33x33 in 16x16 tiles
    EXPECT_EQ(log.values.back(), 1.0);

    ProgressLog cancelling;
    cancelling.cancelAt = 0;
    cb.user = &cancelling;
    pnb_render_settings big = f.settings;
    big.width = big.height = 512;
    big.spp = 64;
    pnb_framebuffer* image = nullptr;
    ASSERT_EQ(pnb_framebuffer_create(&big, &image), PNB_OK);
    EXPECT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &big, image, &cb, nullptr), PNB_ERROR_CANCELLED);
    EXPECT_NE(lastError().find("cancelled"), std::string::npos) << lastError();
    EXPECT_LT(cancelling.values.size(), 1024u);  // far from all tiles
    EXPECT_EQ(pnb_framebuffer_sample_count(image), 0u);
    pnb_framebuffer_destroy(image);
}

// ---------------------------------------------------------------- jobs

struct JobLog {
    std::atomic<int> completions{0};
    std::atomic<int> status{-1};
    std::atomic<int> passes{0};
    std::atomic<bool> hadImage{false};
    std::vector<float> image;
    std::string message;
};

void onPass(const pnb_framebuffer* image, uint32_t done, void* user) {
    auto* log = static_cast<JobLog*>(user);
    EXPECT_EQ(pnb_framebuffer_sample_count(image), done);
    ++log->passes;
}

void onComplete(pnb_status status, const char* message, const pnb_framebuffer* image, void* user) {
    auto* log = static_cast<JobLog*>(user);
    log->status = int(status);
    log->message = message;
    log->hadImage = image != nullptr;
    if (image) {
        log->image.resize(size_t(pnb_framebuffer_width(image)) * size_t(pnb_framebuffer_height(image)) * 4);
        EXPECT_EQ(pnb_framebuffer_read_rgba(image, log->image.data(), log->image.size()), PNB_OK);
    }
    ++log->completions;
}

TEST(CApi, AsyncJobsFinishWithCallbacks) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    JobLog log;
    pnb_async_options options;
    pnb_async_options_init(&options);
    options.pass_samples = 3;
    options.on_pass = onPass;
    options.on_complete = onComplete;
    options.user = &log;
    pnb_render_job* job = nullptr;
    ASSERT_EQ(pnb_render_async(f.renderer, f.prepared, &f.camera, &f.settings, &options, &job), PNB_OK);
    EXPECT_EQ(pnb_render_job_wait(job), PNB_OK);
    EXPECT_EQ(pnb_render_job_done(job), 1);
    EXPECT_EQ(pnb_render_job_progress(job), 1.0);
    EXPECT_EQ(log.completions.load(), 1);
    EXPECT_EQ(log.status.load(), int(PNB_OK));
    EXPECT_EQ(log.message, "");
    EXPECT_EQ(log.passes.load(), 3);  // 3 + 3 + 2 samples
    const pnb_framebuffer* image = nullptr;
    ASSERT_EQ(pnb_render_job_framebuffer(job, &image), PNB_OK);
    EXPECT_EQ(pnb_framebuffer_sample_count(image), 8u);
    EXPECT_EQ(pnb_framebuffer_clear(const_cast<pnb_framebuffer*>(image)), PNB_ERROR_INVALID_ARGUMENT);
    pnb_framebuffer_destroy(const_cast<pnb_framebuffer*>(image));  // ignored: the job owns it

    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    ASSERT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, nullptr, nullptr), PNB_OK);
    EXPECT_TRUE(sameBits(f.read(image), f.read(f.image)));
    EXPECT_TRUE(sameBits(log.image, f.read(f.image)));
    pnb_render_stats stats;
    ASSERT_EQ(pnb_render_job_stats(job, &stats), PNB_OK);
    EXPECT_EQ(stats.samples_per_pixel, 8u);
    pnb_render_job_destroy(job);
}

TEST(CApi, AsyncJobsCancelQuicklyAndSaySo) {
    Fixture f;
    f.buildSphere();
    f.prepare();
    pnb_render_settings big = f.settings;
    big.width = big.height = 1024;
    big.spp = 256;
    JobLog log;
    pnb_async_options options;
    pnb_async_options_init(&options);
    options.on_complete = onComplete;
    options.user = &log;
    pnb_render_job* job = nullptr;
    ASSERT_EQ(pnb_render_async(f.renderer, f.prepared, &f.camera, &big, &options, &job), PNB_OK);
    int done = 1;
    ASSERT_EQ(pnb_render_job_wait_for(job, 50, &done), PNB_OK);
    EXPECT_EQ(done, 0);
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(pnb_render_job_cancel(job), PNB_OK);
    EXPECT_EQ(pnb_render_job_wait(job), PNB_ERROR_CANCELLED);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.2);
    EXPECT_NE(std::string(pnb_render_job_last_error(job)).find("cancelled"), std::string::npos);
    EXPECT_EQ(log.status.load(), int(PNB_ERROR_CANCELLED));
    EXPECT_FALSE(log.hadImage.load());
    const pnb_framebuffer* image = reinterpret_cast<const pnb_framebuffer*>(0x1);
    EXPECT_EQ(pnb_render_job_framebuffer(job, &image), PNB_ERROR_CANCELLED);
    EXPECT_EQ(image, nullptr);
    pnb_render_job_destroy(job);

    // Destroying a running job cancels it.
    ASSERT_EQ(pnb_render_async(f.renderer, f.prepared, &f.camera, &big, nullptr, &job), PNB_OK);
    const auto t1 = std::chrono::steady_clock::now();
    pnb_render_job_destroy(job);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count(), 1.0);
}

// ---------------------------------------------------------------- loading and logging

struct Messages {
    std::vector<std::string> warnings;
};

void collect(pnb_log_level level, const char* message, void* user) {
    if (level == PNB_LOG_WARNING) static_cast<Messages*>(user)->warnings.emplace_back(message);
}

TEST(CApi, LoadsScenesWithRestrictedPathsAndLogsWarnings) {
    Fixture f;
    Messages messages;
    ASSERT_EQ(pnb_renderer_set_log(f.renderer, collect, &messages, PNB_LOG_WARNING), PNB_OK);
    const auto dir = penumbra::test::tempDir();
    penumbra::test::writeFile(dir / "assets" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    const std::string scene = penumbra::test::writeFile(
        dir / "scene" / "s.json",
        R"({"camera": {"eye": [0, 0, 3], "look_at": [0, 0, 0]}, "render": {"width": 20, "height": 10, "spp": 2},
            "shapes": [{"type": "mesh", "file": "../assets/tri.obj"}]})").string();
    pnb_scene* loaded = nullptr;
    EXPECT_EQ(pnb_scene_load(f.renderer, scene.c_str(), nullptr, &loaded), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("outside the allowed directories"), std::string::npos) << lastError();

    const std::string root = (dir / "assets").string();
    const char* roots[] = {root.c_str()};
    pnb_load_options options;
    pnb_load_options_init(&options);
    options.allowed_roots = roots;
    options.allowed_root_count = 1;
    ASSERT_EQ(pnb_scene_load(f.renderer, scene.c_str(), &options, &loaded), PNB_OK) << lastError();
    EXPECT_EQ(pnb_scene_primitive_count(loaded), 1u);
    ASSERT_FALSE(messages.warnings.empty());
    EXPECT_NE(messages.warnings[0].find("tri.obj"), std::string::npos) << messages.warnings[0];

    pnb_camera cam;
    int has = 0;
    ASSERT_EQ(pnb_scene_get_camera(loaded, &cam, &has), PNB_OK);
    EXPECT_EQ(has, 1);
    EXPECT_EQ(cam.eye.z, 3.f);
    pnb_render_settings s;
    ASSERT_EQ(pnb_scene_get_settings(loaded, &s), PNB_OK);
    EXPECT_EQ(s.width, 20);
    EXPECT_EQ(s.spp, 2);
    pnb_scene* copy = nullptr;
    ASSERT_EQ(pnb_scene_clone(loaded, &copy), PNB_OK);
    EXPECT_EQ(pnb_scene_primitive_count(copy), 1u);
    pnb_scene_destroy(copy);
    pnb_scene_destroy(loaded);

    options.allowed_root_count = 0;
    options.restrict_paths = 0;
    ASSERT_EQ(pnb_scene_load(f.renderer, scene.c_str(), &options, &loaded), PNB_OK);
    pnb_scene_destroy(loaded);
}

// pnb_load_options' mesh options (penumbra's --model and --smooth-angle): a PLY
// pyramid without normals loads as the C++ API loads it with the same
// LoadOptions (the same image, bit for bit), the options change the image, and
// bad values are refused naming them.
TEST(CApi, LoadsMeshFilesWithAPhongModelAndSmoothing) {
    Fixture f;
    const auto dir = penumbra::test::tempDir();
    const std::string ply = penumbra::test::writeFile(dir / "pyramid.ply", R"(ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
-1 -1 0
1 -1 0
1 1 0
-1 1 0
0 0 1.2
3 0 1 4
3 1 2 4
3 2 3 4
3 3 0 4
)").string();
    pnb_load_options defaults;
    pnb_load_options_init(&defaults);
    EXPECT_EQ(defaults.use_mesh_model, 0);
    EXPECT_EQ(defaults.mesh_model, PNB_PHONG_NORMALIZED);
    EXPECT_EQ(defaults.smooth_angle_degrees, 30.f);

    f.settings.aovs = 1;
    const size_t pixels = size_t(f.settings.width) * size_t(f.settings.height);
    struct Render {
        std::vector<float> rgba, normals;
    };
    auto renderC = [&](const pnb_load_options& options) {
        pnb_scene* loaded = nullptr;
        Render out;
        EXPECT_EQ(pnb_scene_load(f.renderer, ply.c_str(), &options, &loaded), PNB_OK) << lastError();
        if (!loaded) return out;
        EXPECT_EQ(pnb_scene_add_point_light(loaded, v3(1, 2, 4), gray(20.f)), PNB_OK);
        pnb_prepared_scene* prepared = nullptr;
        pnb_framebuffer* image = nullptr;
        EXPECT_EQ(pnb_prepare(f.renderer, loaded, nullptr, &prepared), PNB_OK) << lastError();
        EXPECT_EQ(pnb_framebuffer_create(&f.settings, &image), PNB_OK);
        EXPECT_EQ(pnb_render(f.renderer, prepared, &f.camera, &f.settings, image, nullptr, nullptr), PNB_OK);
        out.rgba.resize(pixels * 4);
        out.normals.resize(pixels * 3);
        EXPECT_EQ(pnb_framebuffer_read_rgba(image, out.rgba.data(), out.rgba.size()), PNB_OK) << lastError();
        EXPECT_EQ(pnb_framebuffer_read_normals(image, out.normals.data(), out.normals.size()), PNB_OK) << lastError();
        pnb_framebuffer_destroy(image);
        pnb_prepared_scene_destroy(prepared);
        pnb_scene_destroy(loaded);
        return out;
    };
    pnb_load_options classicFaceted = defaults;
    classicFaceted.use_mesh_model = 1;
    classicFaceted.mesh_model = PNB_PHONG_CLASSIC;
    classicFaceted.smooth_angle_degrees = 0.f;
    const Render c = renderC(classicFaceted);

    const pnb::Renderer r([](pnb::LogLevel, std::string_view) {});
    pnb::LoadOptions lo;
    lo.meshModel = pnb::PhongModel::Classic;
    lo.smoothAngleDegrees = 0.f;
    pnb::Scene cpp = r.loadScene(ply, lo);
    cpp.addPointLight({1, 2, 4}, pnb::gray(20.f));
    pnb::RenderSettings st;
    st.width = st.height = 33;
    st.spp = 8;
    st.seed = 3;
    st.aovs = true;
    pnb::Camera cam;
    cam.eye = {0, 0, 4};
    cam.lookAt = {0, 0, 0};
    EXPECT_TRUE(sameBits(c.rgba, r.render(r.prepare(cpp), cam, st).rgba()));

    // Each option changes the image: the model its shading, the angle its normals (the pyramid's
    // faces meet at under 90 degrees: smoothed at 90, faceted at 0).
    pnb_load_options normalized = classicFaceted;
    normalized.mesh_model = PNB_PHONG_NORMALIZED;
    const Render n = renderC(normalized);
    EXPECT_FALSE(sameBits(c.rgba, n.rgba));
    EXPECT_EQ(c.normals, n.normals);
    pnb_load_options smooth = classicFaceted;
    smooth.smooth_angle_degrees = 90.f;
    EXPECT_NE(c.normals, renderC(smooth).normals);

    pnb_scene* loaded = nullptr;
    pnb_load_options bad = defaults;
    bad.use_mesh_model = 1;
    setRaw(bad.mesh_model, 7);
    EXPECT_EQ(pnb_scene_load(f.renderer, ply.c_str(), &bad, &loaded), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("options->mesh_model 7 is not a pnb_phong_model"), std::string::npos) << lastError();
    bad = defaults;
    bad.smooth_angle_degrees = 200.f;
    EXPECT_EQ(pnb_scene_load(f.renderer, ply.c_str(), &bad, &loaded), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("smooth angle must lie in [0, 180] degrees"), std::string::npos) << lastError();
    EXPECT_EQ(loaded, nullptr);
}

TEST(CApi, ErrorsAreKeptPerThread) {
    EXPECT_EQ(pnb_scene_add_sphere(nullptr, v3(0, 0, 0), 1.f, 0), PNB_ERROR_INVALID_ARGUMENT);
    std::string other;
    std::thread t([&] {
        EXPECT_EQ(pnb_prepare(nullptr, nullptr, nullptr, nullptr), PNB_ERROR_INVALID_ARGUMENT);
        other = lastError();
    });
    t.join();
    EXPECT_EQ(other, "pnb_prepare: renderer is NULL");
    EXPECT_EQ(lastError(), "pnb_scene_add_sphere: scene is NULL");
    EXPECT_STREQ(pnb_status_name(PNB_ERROR_CANCELLED), "cancelled");
    EXPECT_STREQ(pnb_version(), PENUMBRA_VERSION);
}

}  // namespace

namespace {

// Instancing through C: the same image as the C++ API's instances, and errors that name the problem.
TEST(CApi, InstancesMatchTheCppApiAndRefuseBadInput) {
    Fixture f;
    pnb_material m;
    pnb_material_init(&m);
    m.kd = pnb_color{0.6f, 0.3f, 0.2f};
    uint32_t id = 0, other = 0;
    ASSERT_EQ(pnb_scene_add_material(f.scene, &m, &id), PNB_OK);
    m.kd = gray(0.9f);
    ASSERT_EQ(pnb_scene_add_material(f.scene, &m, &other), PNB_OK);
    const float pos[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    pnb_mesh_desc mesh;
    pnb_mesh_desc_init(&mesh);
    mesh.positions = pos;
    mesh.vertex_count = 4;
    mesh.indices = idx;
    mesh.triangle_count = 2;
    mesh.material = id;
    uint32_t proto = 99;
    ASSERT_EQ(pnb_scene_add_prototype(f.scene, "quad", &proto), PNB_OK);
    EXPECT_EQ(proto, 0u);
    ASSERT_EQ(pnb_scene_add_prototype_mesh(f.scene, proto, &mesh), PNB_OK) << lastError();
    const float left[12] = {0.5f, 0, 0, -0.6f, 0, 0.5f, 0, 0, 0, 0, 0.5f, 0.5f};  // in front of the third
    const float right[12] = {0, 0, 0.5f, 0.6f, 0, 0.5f, 0, 0, -0.5f, 0, 0, 0};  // turned 90 degrees about y
    ASSERT_EQ(pnb_scene_add_instance(f.scene, proto, left, PNB_KEEP_MATERIALS), PNB_OK) << lastError();
    ASSERT_EQ(pnb_scene_add_instance(f.scene, proto, right, other), PNB_OK) << lastError();
    ASSERT_EQ(pnb_scene_add_instance(f.scene, proto, nullptr, PNB_KEEP_MATERIALS), PNB_OK) << lastError();
    ASSERT_EQ(pnb_scene_add_point_light(f.scene, v3(0.5f, 0.5f, 3), gray(10.f)), PNB_OK);
    EXPECT_EQ(pnb_scene_primitive_count(f.scene), 6u);

    EXPECT_EQ(pnb_scene_add_prototype(f.scene, "x", nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_scene_add_prototype_mesh(f.scene, proto, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_scene_add_instance(f.scene, 5, nullptr, PNB_KEEP_MATERIALS), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("prototype id 5 does not exist"), std::string::npos) << lastError();
    const float flat[12] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0};
    EXPECT_EQ(pnb_scene_add_instance(f.scene, proto, flat, PNB_KEEP_MATERIALS), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("singular"), std::string::npos) << lastError();
    EXPECT_EQ(pnb_scene_add_instance(f.scene, proto, nullptr, 9), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("material id 9"), std::string::npos) << lastError();

    f.prepare();
    ASSERT_EQ(pnb_framebuffer_create(&f.settings, &f.image), PNB_OK);
    ASSERT_EQ(pnb_render(f.renderer, f.prepared, &f.camera, &f.settings, f.image, nullptr, nullptr), PNB_OK);

    pnb::Scene s;
    pnb::Material cm;
    cm.kd = {0.6f, 0.3f, 0.2f};
    pnb::MeshDesc cmesh;
    cmesh.material = s.addMaterial(cm);
    cm.kd = pnb::gray(0.9f);
    const pnb::MaterialId cother = s.addMaterial(cm);
    cmesh.positions = pos;
    cmesh.vertexCount = 4;
    cmesh.indices = idx;
    cmesh.triangleCount = 2;
    const pnb::PrototypeId p = s.addPrototype("quad");
    s.addPrototypeMesh(p, cmesh);
    pnb::Matrix3x4 l, r;
    std::memcpy(l.m, left, sizeof left);
    std::memcpy(r.m, right, sizeof right);
    s.addInstance(p, l);
    s.addInstance(p, r, cother);
    s.addInstance(p, pnb::Matrix3x4{});
    s.addPointLight({0.5f, 0.5f, 3}, pnb::gray(10.f));
    pnb::RenderSettings st;
    st.width = st.height = 33;
    st.spp = 8;
    st.seed = 3;
    pnb::Camera cam;
    cam.eye = {0, 0, 4};
    cam.lookAt = {0, 0, 0};
    const pnb::Renderer rr([](pnb::LogLevel, std::string_view) {});
    const std::vector<float> c = f.read(f.image);
    EXPECT_TRUE(sameBits(c, rr.render(rr.prepare(s), cam, st).rgba()));
    float sum = 0.f;
    for (float v : c) sum += v;
    EXPECT_GT(sum, float(c.size()) * 0.26f);  // alpha alone is a quarter of the values; the quads are lit
}

}  // namespace

TEST(CApi, MetalRoughnessMaterialGivesTheCppApisImage) {
    // A red metal-roughness quad with a metallic-roughness texture in glTF's layout.
    const std::filesystem::path dir = penumbra::test::tempDir();
    // 1 x 1 linear PFM: G (roughness) 0.5, B (metallic) 0.25.
    std::string pfm = "PF\n1 1\n-1.0\n";
    const float texel[3] = {0.f, 0.5f, 0.25f};
    pfm.append(reinterpret_cast<const char*>(texel), sizeof texel);
    const std::string mr = penumbra::test::writeFile(dir / "mr.pfm", pfm).string();
    Fixture f;
    pnb_material m;
    pnb_material_init(&m);
    EXPECT_EQ(m.kind, PNB_MATERIAL_PHONG);
    EXPECT_FLOAT_EQ(m.normal_scale, 1.f);
    m.kind = PNB_MATERIAL_METAL_ROUGHNESS;
    m.base_color = pnb_color{0.8f, 0.2f, 0.1f};
    m.metallic = 1.f;
    m.roughness = 0.8f;
    m.metallic_roughness_texture = mr.c_str();
    pnb::Material cm;
    cm.kind = pnb::MaterialKind::MetalRoughness;
    cm.baseColor = {0.8f, 0.2f, 0.1f};
    cm.metallic = 1.f;
    cm.roughness = 0.8f;
    cm.metallicTexture.path = cm.roughnessTexture.path = mr;
    cm.metallicTexture.channel = 2;
    cm.roughnessTexture.channel = 1;
    const std::vector<float> cpp = expectQuadSameThroughBothApis(f, m, cm);
    // The texture's metallic 0.25 leaves a diffuse red part: red dominates the lit centre.
    const size_t centre = (16 * 33 + 16) * 4;
    EXPECT_GT(cpp[centre], 2.f * cpp[centre + 2]);

    m.kind = static_cast<pnb_material_kind>(7);
    EXPECT_EQ(pnb_scene_add_material(f.scene, &m, nullptr), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pnb_scene_last_error(f.scene)).find("material kind 7"), std::string::npos);
}
