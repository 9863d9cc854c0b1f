// embed_cpp: a host program that embeds Penumbra through its C++ API.
// It builds a small scene in code (a floor, a glossy sphere, a rotated mirror
// box, a mesh from arrays, an area light, a point light), prepares it once,
// renders it in four progressive passes (reading the image between passes)
// and writes a PNG.
//
//   embed_cpp [OUTPUT.png]
#include <cstdint>
#include <cstdio>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    const std::string output = argc > 1 ? argv[1] : "embed_cpp.png";
    try {
        // Messages from the library go where the host wants them.
        pnb::Renderer renderer([](pnb::LogLevel, std::string_view message) {
            std::fprintf(stderr, "embed_cpp: penumbra says: %.*s\n", int(message.size()), message.data());
        });

        pnb::Scene scene;
        pnb::Material floor;
        floor.kd = pnb::gray(0.6f);
        pnb::Material red;
        red.kd = {0.7f, 0.15f, 0.1f};
        red.ks = pnb::gray(0.2f);
        red.exponent = 40.f;
        pnb::Material mirror;
        mirror.kd = pnb::gray(0.05f);
        mirror.kr = pnb::gray(0.85f);
        pnb::Material orange;
        orange.kd = {0.8f, 0.45f, 0.1f};
        pnb::Material lamp;
        lamp.kd = pnb::gray(0.f);
        lamp.ke = pnb::gray(8.f);
        const pnb::MaterialId floorId = scene.addMaterial(floor);
        const pnb::MaterialId redId = scene.addMaterial(red);
        const pnb::MaterialId mirrorId = scene.addMaterial(mirror);
        const pnb::MaterialId orangeId = scene.addMaterial(orange);
        const pnb::MaterialId lampId = scene.addMaterial(lamp);

        scene.addPlane({0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, floorId);
        scene.addSphere({0.f, 0.6f, 0.f}, 0.6f, redId);
        scene.addBox({-0.35f, 0.f, -0.35f}, {0.35f, 0.9f, 0.35f},
                     pnb::Matrix3x4::translate({1.4f, 0.f, -0.6f}) * pnb::Matrix3x4::rotate(30.f, {0.f, 1.f, 0.f}),
                     mirrorId);
        // A square pyramid from host arrays.
        const std::vector<float> positions = {-1.9f, 0.f, -0.3f, -1.1f, 0.f, -0.3f, -1.1f, 0.f, 0.5f,
                                              -1.9f, 0.f, 0.5f,  -1.5f, 0.9f, 0.1f};
        const std::vector<std::uint32_t> indices = {3, 2, 4, 2, 1, 4, 1, 0, 4, 0, 3, 4};
        scene.addMesh(positions, indices, orangeId);
        // A 1 x 1 area light at height 2.5 facing down (cross(a, b) points to -y).
        scene.addRectangle({-0.5f, 2.5f, -0.5f}, {1.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, lampId);
        scene.addPointLight({2.f, 3.f, 3.f}, pnb::gray(15.f));
        scene.setAmbient(pnb::gray(0.03f));
        scene.setBackground({0.08f, 0.1f, 0.16f});

        // Prepare once (BVH, light tables); render as many views as needed.
        const pnb::PreparedScene prepared = renderer.prepare(std::move(scene));

        pnb::Camera camera;
        camera.eye = {0.f, 1.4f, 4.5f};
        camera.lookAt = {0.f, 0.6f, 0.f};
        camera.vfovDegrees = 40.f;
        pnb::RenderSettings settings;
        settings.width = 320;
        settings.height = 240;
        settings.spp = 16;
        settings.seed = 1;

        pnb::Framebuffer image(settings);
        for (std::uint32_t first = 0; first < std::uint32_t(settings.spp); first += 4) {
            renderer.renderPass(prepared, camera, settings, image, first, 4);
            const pnb::Color c = image.pixel(settings.width / 2, settings.height / 2);
            std::printf("embed_cpp: %2u spp, centre pixel (%.3f, %.3f, %.3f)\n", image.sampleCount(), c.r, c.g, c.b);
        }
        image.writeImage(output);
        std::printf("embed_cpp: wrote %s (%dx%d, Penumbra %s)\n", output.c_str(), image.width(), image.height(),
                    pnb::version());
        return 0;
    } catch (const pnb::Error& e) {
        std::fprintf(stderr, "embed_cpp: %s: %s\n", pnb::errorCodeName(e.code()), e.what());
        return 1;
    }
}
