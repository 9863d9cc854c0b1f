// External C++17 host: the same scene as host_c.c through the C++ API. Writes
// argv[1] (PNG) and prints the centre pixel.
#include <cstdio>
#include <penumbra/penumbra.hpp>
#include <string>

static_assert(PENUMBRA_VERSION_MAJOR == 0 && PENUMBRA_VERSION_MINOR >= 1, "unexpected Penumbra version");

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    try {
        if (std::string(pnb::version()) != PENUMBRA_VERSION)
            throw pnb::Error(pnb::ErrorCode::Internal, "version mismatch");
        pnb::Renderer renderer;
        pnb::Scene scene;
        pnb::Material white;
        white.kd = pnb::gray(0.8f);
        const pnb::MaterialId id = scene.addMaterial(white);
        scene.addSphere({0.f, 0.f, 0.f}, 1.f, id);
        scene.addPointLight({0.f, 0.f, 5.f}, pnb::gray(20.f));
        const pnb::PreparedScene prepared = renderer.prepare(scene);
        pnb::Camera camera;
        camera.eye = {0.f, 0.f, 4.f};
        camera.lookAt = {0.f, 0.f, 0.f};
        pnb::RenderSettings settings;
        settings.width = 33;
        settings.height = 33;
        settings.spp = 4;
        const pnb::Framebuffer image = renderer.render(prepared, camera, settings);
        image.writeImage(argv[1]);
        const pnb::Color c = image.pixel(16, 16);
        std::printf("host_cpp %s centre %.4f %.4f %.4f\n", pnb::version(), c.r, c.g, c.b);
        return 0;
    } catch (const pnb::Error& e) {
        std::fprintf(stderr, "host_cpp: %s: %s\n", pnb::errorCodeName(e.code()), e.what());
        return 1;
    }
}
