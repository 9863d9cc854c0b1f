/* embed_c: a host program that embeds Penumbra through its C API (C99).
 * It builds a small scene in code, renders it with a progress display and
 * writes a PNG. Every call returns a pnb_status; on failure the message is in
 * pnb_last_error() (and on the handle the call was made on).
 *
 *   embed_c [OUTPUT.png] */
#include <penumbra/penumbra.h>
#include <stdio.h>

/* Reports a failed call and jumps to the cleanup code. */
#define CHECK(call)                                                                             \
    do {                                                                                        \
        pnb_status status_ = (call);                                                            \
        if (status_ != PNB_OK) {                                                                \
            fprintf(stderr, "embed_c: %s: %s\n", pnb_status_name(status_), pnb_last_error()); \
            goto cleanup;                                                                       \
        }                                                                                       \
    } while (0)

static int on_progress(double fraction, void* user) {
    int* last_tenth = (int*)user;
    int tenth = (int)(fraction * 10.0);
    if (tenth > *last_tenth) {
        *last_tenth = tenth;
        fprintf(stderr, "\rembed_c: %3d%%", tenth * 10);
        if (tenth == 10) fprintf(stderr, "\n");
    }
    return 0; /* nonzero would cancel the render */
}

static pnb_vec3 vec3(float x, float y, float z) {
    pnb_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static pnb_color gray(float v) {
    pnb_color c;
    c.r = c.g = c.b = v;
    return c;
}

int main(int argc, char** argv) {
    const char* output = argc > 1 ? argv[1] : "embed_c.png";
    int result = 1;
    int last_tenth = -1;
    pnb_renderer* renderer = NULL;
    pnb_scene* scene = NULL;
    pnb_prepared_scene* prepared = NULL;
    pnb_framebuffer* image = NULL;
    pnb_material floor, blue, lamp;
    uint32_t floor_id, blue_id, lamp_id;
    pnb_camera camera;
    pnb_render_settings settings;
    pnb_render_callbacks callbacks;
    pnb_render_stats stats;
    pnb_color centre;

    CHECK(pnb_renderer_create(&renderer));
    CHECK(pnb_scene_create(&scene));

    pnb_material_init(&floor);
    floor.name = "floor";
    floor.kd = gray(0.6f);
    pnb_material_init(&blue);
    blue.name = "blue";
    blue.kd.r = 0.1f;
    blue.kd.g = 0.25f;
    blue.kd.b = 0.7f;
    blue.ks = gray(0.2f);
    blue.exponent = 40.f;
    pnb_material_init(&lamp);
    lamp.name = "lamp";
    lamp.kd = gray(0.f);
    lamp.ke = gray(8.f);
    CHECK(pnb_scene_add_material(scene, &floor, &floor_id));
    CHECK(pnb_scene_add_material(scene, &blue, &blue_id));
    CHECK(pnb_scene_add_material(scene, &lamp, &lamp_id));

    CHECK(pnb_scene_add_plane(scene, vec3(0.f, 0.f, 0.f), vec3(0.f, 1.f, 0.f), 1, floor_id));
    CHECK(pnb_scene_add_sphere(scene, vec3(0.f, 0.6f, 0.f), 0.6f, blue_id));
    CHECK(pnb_scene_add_disk(scene, vec3(-1.3f, 0.01f, 0.3f), vec3(0.f, 1.f, 0.f), 0.4f, blue_id));
    CHECK(pnb_scene_add_box(scene, vec3(1.0f, 0.f, -0.6f), vec3(1.6f, 0.7f, 0.f), NULL, floor_id));
    /* A 1 x 1 area light at height 2.5 facing down. */
    CHECK(pnb_scene_add_rectangle(scene, vec3(-0.5f, 2.5f, -0.5f), vec3(1.f, 0.f, 0.f), vec3(0.f, 0.f, 1.f), lamp_id));
    CHECK(pnb_scene_add_point_light(scene, vec3(2.f, 3.f, 3.f), gray(15.f)));
    CHECK(pnb_scene_set_background(scene, gray(0.1f)));

    CHECK(pnb_prepare(renderer, scene, NULL, &prepared));

    pnb_camera_init(&camera);
    camera.eye = vec3(0.f, 1.4f, 4.5f);
    camera.look_at = vec3(0.f, 0.6f, 0.f);
    camera.vfov_degrees = 40.f;
    pnb_render_settings_init(&settings);
    settings.width = 320;
    settings.height = 240;
    settings.spp = 16;
    settings.seed = 1;

    CHECK(pnb_framebuffer_create(&settings, &image));
    pnb_render_callbacks_init(&callbacks);
    callbacks.progress = on_progress;
    callbacks.user = &last_tenth;
    CHECK(pnb_render(renderer, prepared, &camera, &settings, image, &callbacks, &stats));
    CHECK(pnb_framebuffer_pixel(image, settings.width / 2, settings.height / 2, &centre));
    printf("embed_c: %u spp in %.2f s (%.1f Mrays/s), centre pixel (%.3f, %.3f, %.3f)\n", stats.samples_per_pixel,
           stats.render_seconds, stats.mrays_per_second, centre.r, centre.g, centre.b);
    CHECK(pnb_framebuffer_write_image(image, output, NULL));
    printf("embed_c: wrote %s (Penumbra %s)\n", output, pnb_version());
    result = 0;

cleanup:
    pnb_framebuffer_destroy(image);
    pnb_prepared_scene_destroy(prepared);
    pnb_scene_destroy(scene);
    pnb_renderer_destroy(renderer);
    return result;
}
