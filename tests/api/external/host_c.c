/* External C99 host: a white sphere lit head-on by a point light in front of
 * a black background. Writes argv[1] (PNG) and prints the centre pixel. */
#include <penumbra/penumbra.h>
#include <penumbra/version.h>
#include <stdio.h>
#include <string.h>

#if PENUMBRA_VERSION_NUMBER < 100
#error "unexpected PENUMBRA_VERSION_NUMBER"
#endif

static int fail(const char* what, pnb_status status) {
    fprintf(stderr, "host_c: %s: %s (%s)\n", what, pnb_status_name(status), pnb_last_error());
    return 1;
}

int main(int argc, char** argv) {
    pnb_renderer* renderer = NULL;
    pnb_scene* scene = NULL;
    pnb_prepared_scene* prepared = NULL;
    pnb_framebuffer* image = NULL;
    pnb_material white;
    uint32_t id = 0;
    pnb_vec3 centre = {0.f, 0.f, 0.f}, light = {0.f, 0.f, 5.f};
    pnb_color intensity = {20.f, 20.f, 20.f};
    pnb_camera camera;
    pnb_render_settings settings;
    pnb_color pixel;
    pnb_status s;
    if (argc < 2) return 2;
    if (strcmp(pnb_version(), PENUMBRA_VERSION) != 0) return fail("version mismatch", PNB_ERROR_INTERNAL);

    if ((s = pnb_renderer_create(&renderer)) != PNB_OK) return fail("renderer", s);
    if ((s = pnb_scene_create(&scene)) != PNB_OK) return fail("scene", s);
    pnb_material_init(&white);
    white.kd.r = white.kd.g = white.kd.b = 0.8f;
    if ((s = pnb_scene_add_material(scene, &white, &id)) != PNB_OK) return fail("material", s);
    if ((s = pnb_scene_add_sphere(scene, centre, 1.f, id)) != PNB_OK) return fail("sphere", s);
    if ((s = pnb_scene_add_point_light(scene, light, intensity)) != PNB_OK) return fail("light", s);
    if ((s = pnb_prepare(renderer, scene, NULL, &prepared)) != PNB_OK) return fail("prepare", s);

    pnb_camera_init(&camera);
    camera.eye.x = 0.f, camera.eye.y = 0.f, camera.eye.z = 4.f;
    camera.look_at.x = 0.f, camera.look_at.y = 0.f, camera.look_at.z = 0.f;
    pnb_render_settings_init(&settings);
    settings.width = 33;
    settings.height = 33;
    settings.spp = 4;
    if ((s = pnb_framebuffer_create(&settings, &image)) != PNB_OK) return fail("framebuffer", s);
    if ((s = pnb_render(renderer, prepared, &camera, &settings, image, NULL, NULL)) != PNB_OK) return fail("render", s);
    if ((s = pnb_framebuffer_pixel(image, 16, 16, &pixel)) != PNB_OK) return fail("pixel", s);
    if ((s = pnb_framebuffer_write_image(image, argv[1], NULL)) != PNB_OK) return fail("write", s);
    printf("host_c %s centre %.4f %.4f %.4f\n", pnb_version(), pixel.r, pixel.g, pixel.b);

    pnb_framebuffer_destroy(image);
    pnb_prepared_scene_destroy(prepared);
    pnb_scene_destroy(scene);
    pnb_renderer_destroy(renderer);
    return 0;
}
