// Penumbra's C++ embedding API (namespace pnb). Only standard types cross it
// (the plain value types, shared with the library's inside, are in types.hpp);
// Embree, TBB, OpenImageIO and the renderer's internal headers stay inside the
// library. Usable from C++17 and later. See docs/embedding.md.
//
// The flow: build a Scene in code (or Renderer::loadScene a JSON/OBJ file),
// Renderer::prepare it once (validation, BVH, light tables), then render it as
// often as needed: whole images, progressive passes into a Framebuffer, or
// asynchronously with renderAsync. Objects share no global state, so several
// renderers can work in one process at the same time.
#pragma once

#include <penumbra/names.hpp>
#include <penumbra/types.hpp>
#include <penumbra/version.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#ifndef PENUMBRA_API
#if defined(__GNUC__) || defined(__clang__)
#define PENUMBRA_API __attribute__((visibility("default")))
#else
#define PENUMBRA_API
#endif
#endif

namespace pnb {

namespace detail {
struct Access;  // the library's way to the hidden implementations
}

/// Version of the library actually loaded ("0.1.0"); PENUMBRA_VERSION is the
/// version of the headers a host was compiled with.
PENUMBRA_API const char* version() noexcept;

// ---------------------------------------------------------------- logging

/// Receives the library's messages (loader warnings, scene repairs, ...).
/// May be called from render threads; never concurrently for one render.
using LogCallback = std::function<void(LogLevel level, std::string_view message)>;

// ---------------------------------------------------------------- values

/// Affine map as a row-major 3x4 matrix: p' = M * (p, 1). Default: identity.
struct Matrix3x4 {
    float m[3][4] = {{1.f, 0.f, 0.f, 0.f}, {0.f, 1.f, 0.f, 0.f}, {0.f, 0.f, 1.f, 0.f}};

    PENUMBRA_API static Matrix3x4 translate(const Vec3& t);
    PENUMBRA_API static Matrix3x4 scale(const Vec3& s);
    /// Rotation by `degrees` about `axis` (right-handed).
    PENUMBRA_API static Matrix3x4 rotate(float degrees, const Vec3& axis);
    /// this * other: `other` applies first.
    PENUMBRA_API Matrix3x4 operator*(const Matrix3x4& other) const;
};

/// Index of a material in its scene, as returned by Scene::addMaterial.
using MaterialId = std::uint32_t;

/// Index of a prototype in its scene, as returned by Scene::addPrototype.
using PrototypeId = std::uint32_t;

/// A triangle mesh given as arrays the host owns; Scene::addMesh copies them.
struct MeshDesc {
    std::string name;
    const float* positions = nullptr;            ///< 3 floats per vertex
    std::size_t vertexCount = 0;
    const std::uint32_t* indices = nullptr;      ///< 3 per triangle, counter-clockwise = front
    std::size_t triangleCount = 0;
    const float* normals = nullptr;              ///< optional: 3 per vertex (smooth shading)
    const float* uvs = nullptr;                  ///< optional: 2 per vertex
    const std::uint32_t* faceMaterials = nullptr;  ///< optional: one per triangle
    MaterialId material = 0;                     ///< used when faceMaterials is null
};

/// Throws Error(InvalidArgument) naming the offending setting.
PENUMBRA_API void validate(const RenderSettings& settings);
/// Throws Error(InvalidArgument) naming the problem (eye == lookAt, bad fov, ...).
PENUMBRA_API void validate(const Camera& camera);

/// How Renderer::loadScene reads files.
struct LoadOptions {
    /// What would be skipped with a warning (bad OBJ faces, ...) is an error instead.
    bool strict = false;
    /// Only files below the scene file's folder (and allowedRoots) may be read:
    /// MTL files, textures, meshes referenced from JSON. On by default, so that
    /// a scene file cannot make the host read arbitrary files.
    bool restrictPaths = true;
    /// Further folders files may be read from (only used with restrictPaths).
    std::vector<std::string> allowedRoots;
    /// With restrictPaths off: called with each file the loader reads (the
    /// scene file, MTL files, meshes, textures; absolute, symlinks resolved)
    /// and whether it lies outside the scene file's folder and allowedRoots.
    /// Lets a host warn about outside reads, or refuse to write over an input.
    std::function<void(const std::string& path, bool outside)> onRead;
    /// The Phong model of the materials read from mesh and model files (OBJ/MTL,
    /// PLY, glTF, ...); unset: normalised. JSON materials keep their own "model".
    std::optional<PhongModel> meshModel;
    /// Meshes read from files without vertex normals are smoothed across edges
    /// whose faces meet at less than this angle (degrees, [0, 180]); 0 = faceted.
    float smoothAngleDegrees = 30.f;
};

// ---------------------------------------------------------------- scene

class Renderer;
class PreparedScene;

/// A scene description: materials, shapes, meshes, lights, ambient and
/// background light, and optionally a camera and settings from a file. A
/// plain value: copy it, edit it, prepare it as often as needed.
class PENUMBRA_API Scene {
public:
    /// An empty scene (black background, no ambient light).
    Scene();
    ~Scene();
    Scene(const Scene& other);
    Scene& operator=(const Scene& other);
    Scene(Scene&& other) noexcept;
    Scene& operator=(Scene&& other) noexcept;

    /// Adds a material and returns its id. Before any material is added, id 0
    /// names a default grey material.
    MaterialId addMaterial(const Material& material);
    /// Sphere; its front side faces outwards.
    void addSphere(const Vec3& center, float radius, MaterialId material);
    /// Infinite plane through `point`; a one-sided plane is invisible from behind.
    void addPlane(const Vec3& point, const Vec3& normal, MaterialId material, bool twoSided = true);
    /// Axis-aligned box [lo, hi].
    void addBox(const Vec3& lo, const Vec3& hi, MaterialId material);
    /// Box [lo, hi] in object space, placed by worldFromObject (must be invertible).
    void addBox(const Vec3& lo, const Vec3& hi, const Matrix3x4& worldFromObject, MaterialId material);
    /// Parallelogram corner + s*edgeA + t*edgeB (s, t in [0, 1]); front faces cross(edgeA, edgeB).
    void addRectangle(const Vec3& corner, const Vec3& edgeA, const Vec3& edgeB, MaterialId material);
    /// Disk; its front side faces `normal`.
    void addDisk(const Vec3& center, const Vec3& normal, float radius, MaterialId material);
    /// Copies a triangle mesh. Throws Error(InvalidArgument) for out-of-range
    /// indices or material ids, non-finite values or missing arrays.
    void addMesh(const MeshDesc& mesh);
    /// Convenience: positions (3 per vertex) and indices (3 per triangle), one material.
    void addMesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices, MaterialId material);
    /// Isotropic point light of intensity I (W/sr per channel).
    void addPointLight(const Vec3& position, const Color& intensity);
    /// Light travelling along `direction` with irradiance E on a surface facing it.
    void addDirectionalLight(const Vec3& direction, const Color& irradiance);
    /// Global ambient light La (multiplied by each material's ka).
    void setAmbient(const Color& ambient);
    /// Radiance of rays that leave the scene.
    void setBackground(const Color& background);
    /// Stores a camera with the scene (renders still take the camera explicitly).
    void setCamera(const Camera& camera);

    /// The camera a scene file set (or setCamera); empty otherwise.
    std::optional<Camera> camera() const;
    /// camera() if set, else a camera looking along -z that frames the scene's bounds.
    Camera defaultCamera(float aspect, float vfovDegrees = 40.f) const;
    /// Default settings with the scene file's "render" block applied.
    RenderSettings settings() const;

    std::size_t materialCount() const;
    /// Shapes plus triangles.
    std::size_t primitiveCount() const;
    std::size_t triangleCount() const;

    // Instancing: a prototype's meshes are stored once and drawn only through
    // its instances, each an affine placement (docs/embedding.md). Instances
    // of a prototype with an emissive material (or an emissive override) are
    // expanded into ordinary meshes when prepared, so each copy is a light.

    /// Adds an empty prototype (a named group of meshes) and returns its id.
    PrototypeId addPrototype(const std::string& name);
    /// Copies a mesh into a prototype, in the prototype's object space;
    /// checked as addMesh checks it.
    void addPrototypeMesh(PrototypeId prototype, const MeshDesc& mesh);
    /// Places a prototype and returns the instance's index (0, 1, ... in the
    /// order placed), which SceneEdits names it by. worldFromObject must be
    /// finite and invertible; `material`, when given, replaces the material
    /// of every face.
    std::size_t addInstance(PrototypeId prototype, const Matrix3x4& worldFromObject,
                            std::optional<MaterialId> material = std::nullopt);
    std::size_t prototypeCount() const;
    std::size_t instanceCount() const;
    /// Environment light of constant radiance (times `scale`): it lights the
    /// scene from every direction and is what rays leaving the scene see (in
    /// place of the background). docs/rendering.md, "Environment light".
    void setEnvironment(const Color& radiance, float scale = 1.f);
    /// Environment light from a lat-long (equirectangular) image, linear
    /// radiance (EXR, HDR, PFM; 8-bit images are taken as sRGB), times
    /// `scale`, turned by rotateDegrees about +y (counter-clockwise seen from
    /// above). The file is opened now, once (Error naming it when it cannot
    /// be), and decoded by Renderer::prepare (Error(IoError) naming it when it
    /// is not a readable image or exceeds the 1 GiB image budget).
    void setEnvironmentImage(const std::string& path, float rotateDegrees = 0.f, float scale = 1.f);
    /// Removes the environment light.
    void clearEnvironment();
    bool hasEnvironment() const;
    /// On by default: prepare() gives a scene with no light at all (no
    /// emitter, point or directional light, ambient light, environment or
    /// background) a uniform white environment of radiance 1 and logs a
    /// warning, so that it does not render silently black.
    /// PreparedScene::defaultLightAdded() tells when that happened. Off: such a
    /// scene renders black.
    void setDefaultLight(bool enabled);
    bool defaultLight() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    friend struct detail::Access;
};

// ---------------------------------------------------------------- prepared scene

/// Changes to a prepared scene, for Renderer::update. Each names what it
/// changes by the index the Scene gave it (docs/embedding.md, "Editing a
/// prepared scene", says which edits are cheap and what each rebuilds).
struct SceneEdits {
    /// Instance index (Scene::addInstance's result) -> new worldFromObject.
    std::vector<std::pair<std::size_t, Matrix3x4>> transforms;
    /// Material id -> new material (an emissive ke makes it an area light).
    std::vector<std::pair<MaterialId, Material>> materials;
    /// Point light index (in the order added) -> intensity (W/sr per channel).
    std::vector<std::pair<std::size_t, Color>> pointLights;
    /// Directional light index (in the order added) -> irradiance.
    std::vector<std::pair<std::size_t, Color>> directionalLights;
    /// The environment's rotation about +y in degrees, and its scale.
    std::optional<float> environmentRotateDegrees;
    std::optional<float> environmentScale;
};

struct PrepareOptions {
    AcceleratorKind accelerator = AcceleratorKind::Embree;
    BuildQuality quality = BuildQuality::High;
};

/// A scene ready to render: validated and repaired, with its BVH and light
/// tables built. Immutable; a cheap shared handle (copies share the data), safe
/// to render from several threads and renderers at once. Asynchronous renders
/// keep it alive.
class PENUMBRA_API PreparedScene {
public:
    /// An empty handle; rendering it is an InvalidArgument error.
    PreparedScene();
    ~PreparedScene();
    PreparedScene(const PreparedScene&);
    PreparedScene& operator=(const PreparedScene&);
    PreparedScene(PreparedScene&&) noexcept;
    PreparedScene& operator=(PreparedScene&&) noexcept;

    /// False for an empty handle.
    bool valid() const noexcept;
    std::size_t primitiveCount() const;
    std::size_t triangleCount() const;
    /// Point, directional and area lights (emissive shapes and triangles).
    std::size_t lightCount() const;
    /// Triangles and shapes dropped while validating (bad indices, degenerate, ...).
    std::size_t droppedTriangles() const;
    std::size_t droppedShapes() const;
    double buildSeconds() const;
    /// Name of the accelerator built ("embree" or "naive").
    std::string accelerator() const;
    /// What the source Scene said (see Scene::camera, defaultCamera, settings).
    std::optional<Camera> camera() const;
    Camera defaultCamera(float aspect, float vfovDegrees = 40.f) const;
    RenderSettings settings() const;
    /// True when the scene had no light at all and prepare() gave it the
    /// default uniform white environment (Scene::setDefaultLight).
    bool defaultLightAdded() const;

private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
    friend struct detail::Access;
};

// ---------------------------------------------------------------- framebuffer

/// How Framebuffer::writeImage writes.
struct ImageOptions {
    float exposure = 0.f;  ///< stops; PNG/JPG/TIF only (float formats get the values as computed)
    bool aovs = false;     ///< EXR: extra channels; other formats: a sibling <stem>.aovs.exr
};

/// Accumulated samples of one render window (the crop window, or the whole
/// frame), plus the AOVs when the settings ask for them. Readouts give the
/// average over the samples so far; row 0 is the top row. Not thread-safe:
/// do not read it while a render writes into it.
class PENUMBRA_API Framebuffer {
public:
    /// An empty framebuffer (0 x 0).
    Framebuffer();
    /// A framebuffer matching `settings` (size, crop window, AOVs). Throws
    /// Error(InvalidArgument) for bad settings and Error(OutOfMemory) when it
    /// would need more than half the machine's memory.
    explicit Framebuffer(const RenderSettings& settings);
    /// Bytes a framebuffer for `settings` holds (its window, with AOVs if asked for).
    static std::uint64_t bytesNeeded(const RenderSettings& settings);
    ~Framebuffer();
    Framebuffer(const Framebuffer&);
    Framebuffer& operator=(const Framebuffer&);
    Framebuffer(Framebuffer&&) noexcept;
    Framebuffer& operator=(Framebuffer&&) noexcept;

    /// Size of the window held.
    int width() const noexcept;
    int height() const noexcept;
    /// Size of the full frame and the window within it.
    int fullWidth() const noexcept;
    int fullHeight() const noexcept;
    CropWindow window() const noexcept;
    /// Samples per pixel accumulated so far.
    std::uint32_t sampleCount() const noexcept;
    bool hasAovs() const noexcept;
    /// True after a cancelled or failed pass: the sums are partial; clear() before rendering into it again.
    bool incomplete() const noexcept;

    /// Averaged linear radiance as RGBA floats (alpha 1), width*height*4 values.
    std::vector<float> rgba() const;
    /// The same into host memory; throws Error(InvalidArgument) if floatCount < width*height*4.
    void readRgba(float* dst, std::size_t floatCount) const;
    /// First-hit albedo (3 per pixel), shading normal (3 per pixel) and depth
    /// (distance along the camera ray, 1 per pixel; 0 where nothing was hit),
    /// averaged. Throw Error(InvalidArgument) without AOVs or when dst is too small.
    std::vector<float> albedo() const;
    std::vector<float> normals() const;
    std::vector<float> depth() const;
    void readAlbedo(float* dst, std::size_t floatCount) const;
    void readNormals(float* dst, std::size_t floatCount) const;
    void readDepth(float* dst, std::size_t floatCount) const;
    /// Averaged radiance of window pixel (x, y); throws Error(InvalidArgument) outside.
    Color pixel(int x, int y) const;

    /// Forgets all samples.
    void clear();
    /// Copies the pixels of `tile` (a framebuffer of the same full frame whose
    /// window lies inside this one's, rendered elsewhere with the same settings
    /// and crop set to its window) into this one; the sample count becomes the
    /// tile's and its render time is added. Tiles assemble into the exact image
    /// of one render. Throws Error(InvalidArgument) for another frame, a window
    /// outside this one, AOVs in one only, or a sample count other than this
    /// framebuffer's (unless it has none yet).
    void paste(const Framebuffer& tile);
    /// The framebuffer's state as bytes (frame, window, samples, sums; native
    /// byte order), to move it between processes of one machine type (MPI);
    /// deserialize gives it back, and throws Error(InvalidArgument) for bytes
    /// that are not a framebuffer.
    std::vector<std::uint8_t> serialize() const;
    static Framebuffer deserialize(const std::uint8_t* data, std::size_t size);
    /// Writes the averaged radiance: .exr/.hdr/.pfm linear, .png/.jpg/.tif
    /// exposure-scaled and sRGB-encoded. An EXR of a crop window records the
    /// window's place in the full frame (data window inside the display
    /// window), so compositors assemble crops. Written to a temporary file and
    /// renamed, so a failure leaves no partial image. Throws Error(IoError /
    /// InvalidArgument) naming the file.
    void writeImage(const std::string& path, const ImageOptions& options = {}) const;
    /// The bytes writeImage would write to a file of `format` ("png", "jpg",
    /// "exr", "hdr", "pfm", "tif"; any case, with or without the dot), encoded
    /// in memory: for hosts that send or show the image (a web page, a GUI, a
    /// notebook) without a file. With options.aovs only EXR holds the AOVs (as
    /// channels); other formats throw Error(InvalidArgument). An unknown format
    /// is Error(InvalidArgument), an encoder failure Error(IoError).
    std::vector<std::uint8_t> encodeImage(const std::string& format, const ImageOptions& options = {}) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    friend struct detail::Access;
};

/// Checks, without writing anything, that Framebuffer::writeImage could write
/// `path`: a known image format, an existing and writable folder, no
/// directory in the way. Throws Error(InvalidArgument / IoError) naming the file.
PENUMBRA_API void checkImagePath(const std::string& path);

// ---------------------------------------------------------------- rendering

/// Host hooks for one synchronous render call.
struct RenderControl {
    /// Fraction of the call done, in (0, 1], after each tile; the last call
    /// gives exactly 1. Runs on a render thread, never concurrently with itself;
    /// keep it short.
    std::function<void(double fraction)> progress;
    /// The same moments counted in tiles: (tiles done, tiles in this call).
    std::function<void(std::size_t tilesDone, std::size_t tilesTotal)> tileProgress;
    /// When set and it becomes true, the render stops after the tile rows in
    /// flight (well under a second) and the call throws Error(Cancelled).
    const std::atomic<bool>* cancel = nullptr;
};

enum class JobStatus { Running, Finished, Cancelled, Failed };

/// How an asynchronous render ended, given to AsyncOptions::onComplete.
struct JobResult {
    JobStatus status = JobStatus::Running;
    std::optional<Error> error;               ///< set for Cancelled and Failed
    RenderStats stats;
    const Framebuffer* framebuffer = nullptr;  ///< the image (Finished only), valid during the callback
};

struct AsyncOptions {
    /// Fraction of the whole job done; called from render threads (never
    /// concurrently with itself). RenderJob::progress() polls the same value.
    std::function<void(double fraction)> progress;
    /// Samples per progressive pass (0 = all in one pass). After each pass
    /// onPass sees the image so far, on the job's thread, while nothing writes it.
    std::uint32_t passSamples = 0;
    std::function<void(const Framebuffer& image, std::uint32_t samplesDone)> onPass;
    /// Called once on the job's thread when it ends (finished, cancelled or
    /// failed), before wait() returns. Waiting for the job inside any of its
    /// own callbacks (wait(), framebuffer(), stats(), error()) throws Error
    /// (InvalidArgument): it could never return.
    std::function<void(const JobResult& result)> onComplete;
    // The job destroys its copies of these callbacks before wait() returns.
};

/// A running asynchronous render. Move-only; destroying it cancels the render
/// and waits for it. progress(), cancel(), done() and status() may be called
/// from any thread.
class PENUMBRA_API RenderJob {
public:
    /// An empty job (done, Failed).
    RenderJob();
    ~RenderJob();
    RenderJob(RenderJob&&) noexcept;
    RenderJob& operator=(RenderJob&&) noexcept;
    RenderJob(const RenderJob&) = delete;
    RenderJob& operator=(const RenderJob&) = delete;

    /// Fraction of the job done, 0 to 1.
    double progress() const noexcept;
    /// Asks the render to stop; it does within a fraction of a second.
    void cancel() noexcept;
    bool done() const noexcept;
    /// Blocks until the job has ended (and its onComplete has returned).
    void wait() const;
    /// Waits at most `timeout`; returns done().
    bool waitFor(std::chrono::milliseconds timeout) const;
    JobStatus status() const noexcept;
    /// Waits, then returns the error of a cancelled or failed job (empty otherwise).
    std::optional<Error> error() const;
    /// Waits, then returns the stats of all finished passes.
    RenderStats stats() const;
    /// Waits, then returns the image. Throws the job's Error (code Cancelled
    /// for a cancelled job) unless it finished.
    const Framebuffer& framebuffer() const;
    /// Like framebuffer(), but moves the image out of the job.
    Framebuffer takeFramebuffer();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    friend struct detail::Access;
};

/// The entry point: loads, prepares and renders, logging to its callback.
/// Holds no scene: one Renderer renders any number of prepared scenes, and
/// renderers are independent of each other. Its const methods may be called
/// from several threads at once (the log callback then may be too).
class PENUMBRA_API Renderer {
public:
    /// Logs warnings and errors to stderr.
    Renderer();
    /// Logs messages of at least `minLevel` to `log` (an empty callback: stderr).
    explicit Renderer(LogCallback log, LogLevel minLevel = LogLevel::Warning);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Replaces the log callback (not while this renderer is in use elsewhere).
    void setLog(LogCallback log, LogLevel minLevel = LogLevel::Warning);

    /// Reads a .json or .obj scene file (docs/scene-format.md). With
    /// options.restrictPaths (the default) only files below the scene file's
    /// folder and options.allowedRoots may be read. Throws Error naming the
    /// file and line or JSON path.
    Scene loadScene(const std::string& path, const LoadOptions& options = {}) const;

    /// Validates the scene (repairs are logged and counted), builds its BVH
    /// and light tables. The scene is copied (or moved) in and not referenced after.
    PreparedScene prepare(const Scene& scene, const PrepareOptions& options = {}) const;
    PreparedScene prepare(Scene&& scene, const PrepareOptions& options = {}) const;
    /// A new prepared scene: `scene` with `edits` applied, the same bit for
    /// bit as preparing the edited Scene, sharing with `scene` what the edits
    /// leave alone (moving instances commits a new top-level BVH over the
    /// same prototype BVHs). Throws Error(InvalidArgument) naming a bad edit
    /// (an id that names nothing, a singular or non-finite matrix, a
    /// non-finite colour); `scene` is never changed and renders on unaffected.
    PreparedScene update(const PreparedScene& scene, const SceneEdits& edits) const;

    /// Renders all settings.spp samples into a new framebuffer.
    Framebuffer render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                       const RenderControl& control = {}) const;
    /// Renders the samples `image` is missing, [image.sampleCount(), spp).
    RenderStats render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                       Framebuffer& image, const RenderControl& control = {}) const;
    /// Renders all samples and writes RGBA floats (width*height*4, of the
    /// render window) into host memory.
    RenderStats render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings, float* rgba,
                       std::size_t floatCount, const RenderControl& control = {}) const;
    /// One progressive pass: adds samples [firstSample, firstSample +
    /// sampleCount) of the spp-sample set to `image`, which must hold exactly
    /// firstSample samples and match the settings. Passes that cover [0, spp)
    /// give the same image, bit for bit, as one render with the same settings.
    /// AOVs are accumulated when `image` has them. A cancelled pass throws
    /// Error(Cancelled) and leaves `image` incomplete().
    RenderStats renderPass(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                           Framebuffer& image, std::uint32_t firstSample, std::uint32_t sampleCount,
                           const RenderControl& control = {}) const;
    /// Starts rendering all samples on a thread of its own and returns at once.
    /// Arguments are checked and the framebuffer allocated before it starts
    /// (throwing Error); later failures are reported through the job. The job
    /// keeps the scene alive; it does not use the renderer after this call.
    RenderJob renderAsync(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                          AsyncOptions options = {}) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    friend struct detail::Access;
};

}  // namespace pnb
