/* Penumbra's C embedding API: opaque handles, plain C types, status codes.
 * Usable from C99 and C++. See docs/embedding.md.
 *
 * Conventions
 * - Every function that can fail returns a pnb_status (PNB_OK = 0). Objects
 *   are created through an out-pointer, which is set to NULL on failure.
 * - On failure the message (naming the file and line or JSON path where that
 *   applies) is kept in two places: on the handle the call was made on (read
 *   it with pnb_<handle>_last_error) and in a per-thread slot, pnb_last_error(),
 *   which also covers calls that have no handle yet (creation, NULL handles).
 *   Successful calls leave both untouched. The strings stay valid until the
 *   next failing call on that handle / thread.
 * - NULL handles and bad arguments give PNB_ERROR_INVALID_ARGUMENT; nothing
 *   crosses this API as a C++ exception.
 * - pnb_*_destroy(NULL) does nothing. Borrowed pointers (a job's framebuffer,
 *   the framebuffer given to callbacks) must not be destroyed.
 * - Threads: a handle is used by one thread at a time, with these exceptions:
 *   a pnb_prepared_scene may be rendered by several threads and renderers at
 *   once, and pnb_render_job_progress/cancel/done may be called from any
 *   thread. Separate handles share nothing: two renderers may run at once. */
#ifndef PENUMBRA_H
#define PENUMBRA_H

#include <penumbra/version.h>
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__) || defined(__clang__)
#define PNB_API __attribute__((visibility("default")))
#else
#define PNB_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------ status */

typedef enum pnb_status {
    PNB_OK = 0,
    PNB_ERROR_INVALID_ARGUMENT = 1, /* bad argument, setting or NULL handle */
    PNB_ERROR_FILE_NOT_FOUND = 2,
    PNB_ERROR_PARSE = 3,            /* malformed OBJ/MTL/JSON content */
    PNB_ERROR_INVALID_SCENE = 4,    /* scene content that cannot be rendered */
    PNB_ERROR_IO = 5,               /* reading or writing failed */
    PNB_ERROR_OUT_OF_MEMORY = 6,
    PNB_ERROR_CANCELLED = 7,        /* the host cancelled the render */
    PNB_ERROR_EMBREE = 8,           /* the ray-tracing kernel reported an error */
    PNB_ERROR_INTERNAL = 9
} pnb_status;

/* Short English name of a status ("invalid argument", ...). */
PNB_API const char* pnb_status_name(pnb_status status);
/* Message of the calling thread's most recent failing call ("" if none). */
PNB_API const char* pnb_last_error(void);
/* Version of the library actually loaded, e.g. "0.1.0". */
PNB_API const char* pnb_version(void);

/* ------------------------------------------------------------ handles */

typedef struct pnb_renderer pnb_renderer;             /* logging context; loads, prepares, renders */
typedef struct pnb_scene pnb_scene;                   /* editable scene description */
typedef struct pnb_prepared_scene pnb_prepared_scene; /* immutable, ready to render */
typedef struct pnb_framebuffer pnb_framebuffer;       /* accumulated samples (+ AOVs) */
typedef struct pnb_render_job pnb_render_job;         /* an asynchronous render */

/* ------------------------------------------------------------ plain types */

typedef struct pnb_vec3 {
    float x, y, z;
} pnb_vec3;

typedef struct pnb_color {
    float r, g, b;
} pnb_color;

typedef enum pnb_log_level {
    PNB_LOG_DEBUG = 0,
    PNB_LOG_INFO = 1,
    PNB_LOG_WARNING = 2,
    PNB_LOG_ERROR = 3
} pnb_log_level;

/* Receives library messages; may be called from render threads. */
typedef void (*pnb_log_fn)(pnb_log_level level, const char* message, void* user);

typedef enum pnb_phong_model { PNB_PHONG_NORMALIZED = 0, PNB_PHONG_CLASSIC = 1 } pnb_phong_model;
/* The reflection model: the Phong terms, or glTF 2.0's metal-roughness BSDF (docs/rendering.md). */
typedef enum pnb_material_kind { PNB_MATERIAL_PHONG = 0, PNB_MATERIAL_METAL_ROUGHNESS = 1 } pnb_material_kind;

/* Phong material; fill with pnb_material_init first. */
typedef struct pnb_material {
    const char* name;              /* may be NULL */
    pnb_color ka, kd, ks;          /* ambient, diffuse, specular reflectance */
    float exponent;                /* Phong exponent n */
    pnb_color kr;                  /* mirror reflectance */
    pnb_color ke;                  /* emitted radiance (an area light) */
    int two_sided_emission;
    pnb_phong_model model;
    const char* diffuse_texture;   /* image path multiplying kd through mesh UVs; NULL = none */
    pnb_color kt;                  /* transmission colour: non-zero makes the surface glass (a dielectric) */
    float ior;                     /* index of refraction behind the front side (used when kt is non-zero) */
    pnb_material_kind kind;        /* PNB_MATERIAL_METAL_ROUGHNESS: the fields below (the Phong terms but ke are ignored) */
    pnb_color base_color;          /* linear RGB */
    float metallic, roughness;     /* in [0, 1] */
    float transmission;            /* in [0, 1]: the non-metal part's share that refracts (smooth glass, ior) */
    const char* base_color_texture;         /* sRGB image multiplying base_color; NULL = none */
    const char* metallic_roughness_texture; /* linear, glTF's layout: B multiplies metallic, G roughness; NULL = none */
    const char* normal_texture;             /* tangent-space normal map (either kind); NULL = none */
    float normal_scale;                     /* scales the normal map's X and Y */
    const char* emissive_texture;           /* sRGB image multiplying ke (either kind); NULL = none */
} pnb_material;

/* A triangle mesh in host arrays (copied by pnb_scene_add_mesh); fill with pnb_mesh_desc_init first. */
typedef struct pnb_mesh_desc {
    const char* name;               /* may be NULL */
    const float* positions;         /* 3 floats per vertex */
    size_t vertex_count;
    const uint32_t* indices;        /* 3 per triangle, counter-clockwise = front */
    size_t triangle_count;
    const float* normals;           /* optional (NULL): 3 per vertex */
    const float* uvs;               /* optional (NULL): 2 per vertex */
    const uint32_t* face_materials; /* optional (NULL): one per triangle */
    uint32_t material;              /* used when face_materials is NULL */
} pnb_mesh_desc;

typedef struct pnb_camera {
    pnb_vec3 eye, look_at, up;
    float vfov_degrees;
    float aperture;       /* lens radius; 0 = pinhole */
    float focus_distance; /* 0 = distance from eye to look_at */
} pnb_camera;

/* How light samples choose their lights (docs/rendering.md, "Many lights"); PNB_LIGHTS_AUTO is the default. */
typedef enum pnb_light_selection {
    PNB_LIGHTS_ALL = 0,
    PNB_LIGHTS_POWER = 1,
    PNB_LIGHTS_TREE = 2,
    PNB_LIGHTS_AUTO = 3
} pnb_light_selection;
/* Area-light estimator (docs/rendering.md): light + BRDF samples with MIS (default), or light samples only. */
typedef enum pnb_direct_light { PNB_DIRECT_LIGHT_MIS = 0, PNB_DIRECT_LIGHT_LIGHT = 1 } pnb_direct_light;

typedef enum pnb_integrator { PNB_INTEGRATOR_WHITTED = 0, PNB_INTEGRATOR_PATH = 1 } pnb_integrator;

/* Fill with pnb_render_settings_init first. */
typedef struct pnb_render_settings {
    int width, height;
    int spp;           /* camera samples per pixel */
    int light_samples; /* area-light samples per light per shading point */
    int max_depth;     /* whitted: mirror/refraction bounces; path: path length */
    uint64_t seed;
    int threads;       /* 0 = all cores */
    int tile_size;
    int use_crop;      /* nonzero: render only [crop_x0, crop_x1) x [crop_y0, crop_y1) */
    int crop_x0, crop_y0, crop_x1, crop_y1;
    pnb_light_selection light_selection;
    int aovs;          /* nonzero: framebuffers also hold albedo, normal, depth */
    pnb_integrator integrator;
    pnb_direct_light direct_light;
} pnb_render_settings;

/* Fill with pnb_load_options_init first. */
typedef struct pnb_load_options {
    int strict;                       /* skippable problems become errors */
    int restrict_paths;               /* default 1: read only below the scene's folder and allowed_roots */
    const char* const* allowed_roots; /* further folders (may be NULL) */
    size_t allowed_root_count;
    /* Mesh and model files (OBJ/MTL, PLY, glTF, ...), as penumbra's --model and --smooth-angle; a
       JSON mesh entry's own "model" and "smooth_angle" override them. */
    int use_mesh_model;               /* nonzero: their materials use mesh_model; 0 (default): as read */
    pnb_phong_model mesh_model;
    float smooth_angle_degrees;       /* default 30: meshes without normals are smoothed across edges
                                         whose faces meet at less than this, in [0, 180]; 0 = faceted */
} pnb_load_options;

typedef enum pnb_build_quality { PNB_BUILD_LOW = 0, PNB_BUILD_MEDIUM = 1, PNB_BUILD_HIGH = 2 } pnb_build_quality;

typedef enum pnb_accelerator { PNB_ACCEL_EMBREE = 0, PNB_ACCEL_NAIVE = 1 } pnb_accelerator;

typedef struct pnb_prepare_options {
    pnb_accelerator accelerator; /* PNB_ACCEL_EMBREE (default) or PNB_ACCEL_NAIVE, the O(N) reference */
    pnb_build_quality quality;
} pnb_prepare_options;

typedef struct pnb_prepared_info {
    size_t primitive_count, triangle_count, light_count;
    size_t dropped_triangles, dropped_shapes;
    double build_seconds;
    int default_light_added; /* 1: the scene had no light and got the default white environment */
} pnb_prepared_info;

typedef struct pnb_image_options {
    float exposure; /* stops; PNG/JPG/TIF only */
    int aovs;       /* EXR: extra channels; others: a sibling <stem>.aovs.exr */
} pnb_image_options;

typedef struct pnb_render_stats {
    uint64_t camera_rays, shadow_rays, reflection_rays, invalid_rays, non_finite_samples;
    double render_seconds, mrays_per_second;
    uint32_t samples_per_pixel;
    int threads;
    uint64_t transmission_rays, indirect_rays;
    uint64_t path_length_sum; /* rays along each camera sample's path, summed (mean = sum / camera_rays) */
    uint32_t path_length_max;
    uint64_t brdf_rays; /* whitted: BRDF-sampled direct-light rays traced under MIS (docs/rendering.md) */
    uint64_t pixels_hit; /* pixels whose first camera sample (of each pass) hit a surface */
} pnb_render_stats;

/* Hooks for a synchronous render; fill with zeros or pnb_render_callbacks_init. progress gets the
 * fraction done after each tile (the last call gives exactly 1) on a render thread, never
 * concurrently with itself; returning nonzero cancels the render (it then returns PNB_ERROR_CANCELLED). */
typedef struct pnb_render_callbacks {
    int (*progress)(double fraction, void* user);
    void* user;
} pnb_render_callbacks;

/* Options of an asynchronous render; fill with pnb_async_options_init. Callbacks run on the job's
 * threads. on_pass sees the image after each pass of pass_samples samples (0 = one pass), while
 * nothing writes it. on_complete runs once when the job ends, before pnb_render_job_wait returns,
 * with the outcome, its message ("" on success) and the image (NULL unless it finished); it must
 * not wait on its own job. */
typedef struct pnb_async_options {
    void (*progress)(double fraction, void* user);
    uint32_t pass_samples;
    void (*on_pass)(const pnb_framebuffer* image, uint32_t samples_done, void* user);
    void (*on_complete)(pnb_status status, const char* message, const pnb_framebuffer* image, void* user);
    void* user;
} pnb_async_options;

/* Defaults (the same as the C++ API's). NULL pointers are ignored. */
PNB_API void pnb_material_init(pnb_material* material);
PNB_API void pnb_mesh_desc_init(pnb_mesh_desc* mesh);
PNB_API void pnb_camera_init(pnb_camera* camera);
PNB_API void pnb_render_settings_init(pnb_render_settings* settings);
PNB_API void pnb_load_options_init(pnb_load_options* options);
PNB_API void pnb_prepare_options_init(pnb_prepare_options* options);
PNB_API void pnb_image_options_init(pnb_image_options* options);
PNB_API void pnb_render_callbacks_init(pnb_render_callbacks* callbacks);
PNB_API void pnb_async_options_init(pnb_async_options* options);

/* Checks settings / a camera; the message names the offending value. */
PNB_API pnb_status pnb_render_settings_validate(const pnb_render_settings* settings);
PNB_API pnb_status pnb_camera_validate(const pnb_camera* camera);

/* ------------------------------------------------------------ renderer */

/* A renderer logging warnings and errors to stderr. */
PNB_API pnb_status pnb_renderer_create(pnb_renderer** out);
PNB_API void pnb_renderer_destroy(pnb_renderer* renderer);
/* Sends messages of at least min_level to fn (NULL fn: stderr). */
PNB_API pnb_status pnb_renderer_set_log(pnb_renderer* renderer, pnb_log_fn fn, void* user, pnb_log_level min_level);
PNB_API const char* pnb_renderer_last_error(const pnb_renderer* renderer);

/* ------------------------------------------------------------ scene */

PNB_API pnb_status pnb_scene_create(pnb_scene** out);
/* Reads a .json, .obj or model file (PLY, STL, glTF, ... through Assimp); options NULL: defaults,
   paths restricted to the file's folder. */
PNB_API pnb_status pnb_scene_load(pnb_renderer* renderer, const char* path, const pnb_load_options* options,
                                  pnb_scene** out);
PNB_API pnb_status pnb_scene_clone(const pnb_scene* scene, pnb_scene** out);
PNB_API void pnb_scene_destroy(pnb_scene* scene);
PNB_API const char* pnb_scene_last_error(const pnb_scene* scene);

/* Material ids are what pnb_scene_add_material returned; before any material is added, id 0 is a default grey. */
PNB_API pnb_status pnb_scene_add_material(pnb_scene* scene, const pnb_material* material, uint32_t* out_id);
PNB_API pnb_status pnb_scene_add_sphere(pnb_scene* scene, pnb_vec3 center, float radius, uint32_t material);
PNB_API pnb_status pnb_scene_add_plane(pnb_scene* scene, pnb_vec3 point, pnb_vec3 normal, int two_sided,
                                       uint32_t material);
/* world_from_object: 12 floats, a row-major 3x4 affine matrix; NULL = axis-aligned. */
PNB_API pnb_status pnb_scene_add_box(pnb_scene* scene, pnb_vec3 lo, pnb_vec3 hi, const float* world_from_object,
                                     uint32_t material);
PNB_API pnb_status pnb_scene_add_rectangle(pnb_scene* scene, pnb_vec3 corner, pnb_vec3 edge_a, pnb_vec3 edge_b,
                                           uint32_t material);
PNB_API pnb_status pnb_scene_add_disk(pnb_scene* scene, pnb_vec3 center, pnb_vec3 normal, float radius,
                                      uint32_t material);
PNB_API pnb_status pnb_scene_add_mesh(pnb_scene* scene, const pnb_mesh_desc* mesh);
PNB_API pnb_status pnb_scene_add_point_light(pnb_scene* scene, pnb_vec3 position, pnb_color intensity);
PNB_API pnb_status pnb_scene_add_directional_light(pnb_scene* scene, pnb_vec3 direction, pnb_color irradiance);
PNB_API pnb_status pnb_scene_set_ambient(pnb_scene* scene, pnb_color ambient);
PNB_API pnb_status pnb_scene_set_background(pnb_scene* scene, pnb_color background);
PNB_API pnb_status pnb_scene_set_camera(pnb_scene* scene, const pnb_camera* camera);
/* The scene file's camera (or set_camera's): *has_camera = 0 when there is none. */
PNB_API pnb_status pnb_scene_get_camera(const pnb_scene* scene, pnb_camera* out, int* has_camera);
/* The scene's camera, else one looking along -z that frames its bounds. */
PNB_API pnb_status pnb_scene_default_camera(const pnb_scene* scene, float aspect, float vfov_degrees,
                                            pnb_camera* out);
/* Default settings with the scene file's "render" block applied. */
PNB_API pnb_status pnb_scene_get_settings(const pnb_scene* scene, pnb_render_settings* out);
/* Shapes plus triangles (0 for NULL). */
PNB_API size_t pnb_scene_primitive_count(const pnb_scene* scene);
/* Environment light (docs/rendering.md): a constant radiance times scale, or a lat-long image (opened now,
   decoded by pnb_prepare; errors name the file) times scale, turned by rotate_degrees about +y. */
PNB_API pnb_status pnb_scene_set_environment(pnb_scene* scene, pnb_color radiance, float scale);
PNB_API pnb_status pnb_scene_set_environment_image(pnb_scene* scene, const char* path, float rotate_degrees,
                                                   float scale);
PNB_API pnb_status pnb_scene_clear_environment(pnb_scene* scene);
/* enabled = 1 (the default): pnb_prepare gives a scene with no light at all a uniform white environment of
   radiance 1 and warns (pnb_prepared_info.default_light_added); 0: such a scene renders black. */
PNB_API pnb_status pnb_scene_set_default_light(pnb_scene* scene, int enabled);

/* Instancing: a prototype's meshes are stored once and drawn only through its instances (docs/embedding.md).
   pnb_scene_add_prototype returns the new, empty prototype's id in *out_id. */
PNB_API pnb_status pnb_scene_add_prototype(pnb_scene* scene, const char* name, uint32_t* out_id);
/* Copies a mesh into a prototype (object space), checked as pnb_scene_add_mesh checks it. */
PNB_API pnb_status pnb_scene_add_prototype_mesh(pnb_scene* scene, uint32_t prototype, const pnb_mesh_desc* mesh);
/* Material value of pnb_scene_add_instance that keeps the prototype's own materials. */
#define PNB_KEEP_MATERIALS 0xFFFFFFFFu
/* world_from_object: 12 floats, a row-major 3x4 affine matrix (invertible); NULL = identity.
   material: replaces every face's material, or PNB_KEEP_MATERIALS. The instance's index, which
   pnb_transform_edit names it by, is the number of instances added before it. */
PNB_API pnb_status pnb_scene_add_instance(pnb_scene* scene, uint32_t prototype, const float* world_from_object,
                                          uint32_t material);

/* ------------------------------------------------------------ prepared scene */

/* Validates the scene and builds its BVH and light tables (the scene is copied: it stays usable). */
PNB_API pnb_status pnb_prepare(pnb_renderer* renderer, const pnb_scene* scene, const pnb_prepare_options* options,
                               pnb_prepared_scene** out);
/* Edits of a prepared scene for pnb_update (docs/embedding.md, "Editing a prepared scene"). Each names
   what it changes by the index the scene gave it: instances and lights in the order added, material ids. */
typedef struct pnb_transform_edit {
    uint32_t instance;
    float world_from_object[12]; /* row-major 3x4, finite and invertible */
} pnb_transform_edit;
typedef struct pnb_material_edit {
    uint32_t material;
    pnb_material value;
} pnb_material_edit;
typedef struct pnb_light_edit {
    uint32_t light;
    pnb_color value; /* a point light's intensity, a directional light's irradiance */
} pnb_light_edit;
/* Fill with pnb_scene_edits_init first (no edits); each array holds its count of edits. */
typedef struct pnb_scene_edits {
    const pnb_transform_edit* transforms;
    size_t transform_count;
    const pnb_material_edit* materials;
    size_t material_count;
    const pnb_light_edit* point_lights;
    size_t point_light_count;
    const pnb_light_edit* directional_lights;
    size_t directional_light_count;
    int set_environment_rotation; /* non-zero: turn the environment to environment_rotate_degrees about +y */
    float environment_rotate_degrees;
    int set_environment_scale; /* non-zero: scale the environment by environment_scale */
    float environment_scale;
} pnb_scene_edits;
PNB_API void pnb_scene_edits_init(pnb_scene_edits* edits);
/* A new prepared scene in *out: base with the edits applied, the same image bit for bit as preparing the
   edited scene, sharing with base what the edits leave alone. A bad edit (an index that names nothing, a
   singular or non-finite matrix, a non-finite colour) is PNB_ERROR_INVALID_ARGUMENT naming it (see
   pnb_renderer_last_error); base is never changed and stays usable. */
PNB_API pnb_status pnb_update(pnb_renderer* renderer, const pnb_prepared_scene* base, const pnb_scene_edits* edits,
                              pnb_prepared_scene** out);
/* Running jobs keep the prepared data alive after this. */
PNB_API void pnb_prepared_scene_destroy(pnb_prepared_scene* prepared);
PNB_API pnb_status pnb_prepared_scene_get_info(const pnb_prepared_scene* prepared, pnb_prepared_info* out);
PNB_API pnb_status pnb_prepared_scene_default_camera(const pnb_prepared_scene* prepared, float aspect,
                                                     float vfov_degrees, pnb_camera* out);
PNB_API pnb_status pnb_prepared_scene_get_settings(const pnb_prepared_scene* prepared, pnb_render_settings* out);

/* ------------------------------------------------------------ framebuffer */

/* A framebuffer matching the settings (size, crop, AOVs); PNB_ERROR_OUT_OF_MEMORY when it would need
 * more than half the machine's memory. */
PNB_API pnb_status pnb_framebuffer_create(const pnb_render_settings* settings, pnb_framebuffer** out);
PNB_API void pnb_framebuffer_destroy(pnb_framebuffer* image);
PNB_API const char* pnb_framebuffer_last_error(const pnb_framebuffer* image);
/* Size of the window held (0 for NULL) and samples per pixel so far. */
PNB_API int pnb_framebuffer_width(const pnb_framebuffer* image);
PNB_API int pnb_framebuffer_height(const pnb_framebuffer* image);
PNB_API uint32_t pnb_framebuffer_sample_count(const pnb_framebuffer* image);
/* Averaged values, row 0 on top: RGBA (4 floats per pixel, alpha 1), albedo and normals (3),
 * depth (1). count is the number of floats dst holds. */
PNB_API pnb_status pnb_framebuffer_read_rgba(const pnb_framebuffer* image, float* dst, size_t count);
PNB_API pnb_status pnb_framebuffer_read_albedo(const pnb_framebuffer* image, float* dst, size_t count);
PNB_API pnb_status pnb_framebuffer_read_normals(const pnb_framebuffer* image, float* dst, size_t count);
PNB_API pnb_status pnb_framebuffer_read_depth(const pnb_framebuffer* image, float* dst, size_t count);
PNB_API pnb_status pnb_framebuffer_pixel(const pnb_framebuffer* image, int x, int y, pnb_color* out);
PNB_API pnb_status pnb_framebuffer_clear(pnb_framebuffer* image);
/* .exr/.hdr/.pfm linear; .png/.jpg/.tif exposure-scaled and sRGB-encoded (options NULL: defaults). */
PNB_API pnb_status pnb_framebuffer_write_image(const pnb_framebuffer* image, const char* path,
                                               const pnb_image_options* options);
/* The bytes pnb_framebuffer_write_image would write to a file of `format` ("png", "jpg", "exr", "hdr",
 * "pfm", "tif"), encoded in memory: *out_data (free it with pnb_bytes_free) and *out_size. With
 * options->aovs only "exr" holds the AOVs; other formats are PNB_ERROR_INVALID_ARGUMENT. */
PNB_API pnb_status pnb_framebuffer_encode_image(const pnb_framebuffer* image, const char* format,
                                                const pnb_image_options* options, uint8_t** out_data,
                                                size_t* out_size);
/* Frees what pnb_framebuffer_encode_image returned (NULL: nothing). */
PNB_API void pnb_bytes_free(uint8_t* data);

/* ------------------------------------------------------------ rendering */

/* Renders the samples `image` is missing, [sample_count, spp). callbacks and stats may be NULL. */
PNB_API pnb_status pnb_render(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                              const pnb_render_settings* settings, pnb_framebuffer* image,
                              const pnb_render_callbacks* callbacks, pnb_render_stats* stats);
/* Renders all samples and writes RGBA floats (4 per pixel of the render window) into rgba. */
PNB_API pnb_status pnb_render_rgba(pnb_renderer* renderer, const pnb_prepared_scene* prepared,
                                   const pnb_camera* camera, const pnb_render_settings* settings, float* rgba,
                                   size_t count, const pnb_render_callbacks* callbacks, pnb_render_stats* stats);
/* One progressive pass: adds samples [first_sample, first_sample + sample_count) to `image`, which must
 * hold exactly first_sample samples. Passes covering [0, spp) give the one-shot image bit for bit. A
 * cancelled pass leaves `image` partial: clear it before rendering into it again. */
PNB_API pnb_status pnb_render_pass(pnb_renderer* renderer, const pnb_prepared_scene* prepared,
                                   const pnb_camera* camera, const pnb_render_settings* settings,
                                   pnb_framebuffer* image, uint32_t first_sample, uint32_t sample_count,
                                   const pnb_render_callbacks* callbacks, pnb_render_stats* stats);

/* Starts rendering all samples on a thread of its own (options may be NULL). */
PNB_API pnb_status pnb_render_async(pnb_renderer* renderer, const pnb_prepared_scene* prepared,
                                    const pnb_camera* camera, const pnb_render_settings* settings,
                                    const pnb_async_options* options, pnb_render_job** out);
/* Fraction done, 0 to 1 (0 for NULL). */
PNB_API double pnb_render_job_progress(const pnb_render_job* job);
/* Asks the job to stop; it does within a fraction of a second. */
PNB_API pnb_status pnb_render_job_cancel(pnb_render_job* job);
PNB_API int pnb_render_job_done(const pnb_render_job* job);
/* Blocks until the job ends; returns its outcome: PNB_OK, PNB_ERROR_CANCELLED or the failure. */
PNB_API pnb_status pnb_render_job_wait(pnb_render_job* job);
/* Waits at most timeout_ms; *done tells whether it ended. */
PNB_API pnb_status pnb_render_job_wait_for(pnb_render_job* job, uint32_t timeout_ms, int* done);
/* Waits, then lends the finished image (valid until the job is destroyed). */
PNB_API pnb_status pnb_render_job_framebuffer(pnb_render_job* job, const pnb_framebuffer** out);
PNB_API pnb_status pnb_render_job_stats(pnb_render_job* job, pnb_render_stats* out);
/* Cancels a running job and waits for it. */
PNB_API void pnb_render_job_destroy(pnb_render_job* job);
PNB_API const char* pnb_render_job_last_error(const pnb_render_job* job);

#ifdef __cplusplus
}
#endif

#endif /* PENUMBRA_H */
