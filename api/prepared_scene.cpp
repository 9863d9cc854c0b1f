// pnb::PreparedScene, and the Renderer's entry points that make one:
// logging, loading a scene file, preparing.
#include "api/api_internal.h"

#include <cmath>
#include <filesystem>

#include "core/io/scene_loader.h"

namespace pnb {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- PreparedScene

PreparedScene::PreparedScene() = default;
PreparedScene::~PreparedScene() = default;
PreparedScene::PreparedScene(const PreparedScene&) = default;
PreparedScene& PreparedScene::operator=(const PreparedScene&) = default;
PreparedScene::PreparedScene(PreparedScene&&) noexcept = default;
PreparedScene& PreparedScene::operator=(PreparedScene&&) noexcept = default;

bool PreparedScene::valid() const noexcept { return impl_ != nullptr; }
std::size_t PreparedScene::primitiveCount() const { return requirePrepared(*this).prepared.scene().primitiveCount(); }
std::size_t PreparedScene::triangleCount() const { return requirePrepared(*this).prepared.scene().triangleCount(); }
std::size_t PreparedScene::lightCount() const { return requirePrepared(*this).prepared.lights().size(); }
std::size_t PreparedScene::droppedTriangles() const {
    return requirePrepared(*this).prepared.fixups().droppedTriangles;
}
std::size_t PreparedScene::droppedShapes() const { return requirePrepared(*this).prepared.fixups().droppedShapes; }
double PreparedScene::buildSeconds() const { return requirePrepared(*this).prepared.buildSeconds(); }
std::string PreparedScene::accelerator() const { return requirePrepared(*this).prepared.accelerator().name(); }

std::optional<Camera> PreparedScene::camera() const {
    const Impl& p = requirePrepared(*this);
    if (!p.camera) return std::nullopt;
    return *p.camera;
}

Camera PreparedScene::defaultCamera(float aspect, float vfovDegrees) const {
    const Impl& p = requirePrepared(*this);
    return guarded([&] { return defaultCameraFor(p.camera, p.prepared.scene().bounds(), aspect, vfovDegrees); });
}

RenderSettings PreparedScene::settings() const { return settingsFrom(requirePrepared(*this).settings); }
bool PreparedScene::defaultLightAdded() const { return requirePrepared(*this).prepared.defaultLightAdded(); }

// ---------------------------------------------------------------- Renderer

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::Renderer(LogCallback log, LogLevel minLevel) : impl_(std::make_unique<Impl>()) {
    setLog(std::move(log), minLevel);
}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&& o) noexcept : impl_(std::move(o.impl_)) {
    o.impl_ = std::unique_ptr<Impl>(new (std::nothrow) Impl());
}
Renderer& Renderer::operator=(Renderer&& o) noexcept {
    std::swap(impl_, o.impl_);
    return *this;
}

void Renderer::setLog(LogCallback log, LogLevel minLevel) {
    if (log) {
        impl_->log = pn::Logger(std::move(log), minLevel);
    } else {
        impl_->log = pn::Logger();
        impl_->log.setMinLevel(minLevel);
    }
}

Scene Renderer::loadScene(const std::string& path, const LoadOptions& options) const {
    return guarded([&] {
        require(!path.empty(), "scene path is empty");
        pn::LoadOptions lo;
        lo.strict = options.strict;
        require(std::isfinite(options.smoothAngleDegrees) && options.smoothAngleDegrees >= 0.f &&
                    options.smoothAngleDegrees <= 180.f,
                "smooth angle must lie in [0, 180] degrees");
        lo.meshModel = options.meshModel;
        lo.smoothAngleDegrees = options.smoothAngleDegrees;
        // The scene's own folder, so its MTL files, textures and meshes stay readable.
        std::vector<fs::path> roots{fs::absolute(fs::path(path)).parent_path()};
        for (const std::string& root : options.allowedRoots) {
            require(!root.empty(), "allowed root is empty");
            roots.push_back(fs::absolute(fs::path(root)));
        }
        if (options.restrictPaths) {
            lo.allowedRoots = roots;
        } else if (options.onRead) {
            // Unrestricted loading reports the files read outside its notice
            // roots; a root below which nothing lies makes that every file.
            // Whether a file is outside the real roots is then the same
            // path rule, asked of checkPathAllowed.
            lo.noticeRoots = {fs::path("/") / ".penumbra: report every file read"};
            pn::LoadOptions restricted;
            restricted.allowedRoots = roots;
            lo.onReadOutside = [&options, restricted](const fs::path& f) {
                bool outside = false;
                try {
                    pn::checkPathAllowed(f, restricted);
                } catch (const Error&) {
                    outside = true;
                }
                options.onRead(f.string(), outside);
            };
        }
        pn::LoadedScene loaded = pn::loadScene(path, lo, impl_->log);
        Scene scene;
        SceneImpl& s = Access::of(scene);
        s.scene = std::move(loaded.scene);
        s.camera = loaded.camera;
        s.settings = loaded.settings;
        s.source = path;
        return scene;
    });
}

PreparedScene Renderer::prepare(const Scene& scene, const PrepareOptions& options) const {
    return prepare(Scene(scene), options);
}

PreparedScene Renderer::prepare(Scene&& scene, const PrepareOptions& options) const {
    return guarded([&] {
        SceneImpl& s = Access::of(scene);
        pn::PrepareOptions po;
        po.accelerator = options.accelerator;
        po.quality = options.quality;
        std::shared_ptr<const PreparedImpl> impl;
        try {
            impl = std::make_shared<const PreparedImpl>(std::move(s.scene), po, impl_->log, s.camera, s.settings);
        } catch (const Error& e) {
            // The accelerator's errors (Embree's device errors, out of memory
            // in the BVH build) know nothing of files: name the scene's.
            const bool fromBuild = e.code() == ErrorCode::Embree || e.code() == ErrorCode::OutOfMemory;
            if (!fromBuild || s.source.empty()) throw;
            throw Error(e.code(), s.source + ": " + e.what());
        } catch (const std::bad_alloc&) {
            if (s.source.empty()) throw;
            throw Error(ErrorCode::OutOfMemory, s.source + ": out of memory while preparing the scene");
        }
        s = SceneImpl{};  // the moved-from scene is empty, not half-moved
        PreparedScene p;
        Access::set(p, std::move(impl));
        return p;
    });
}

PreparedScene Renderer::update(const PreparedScene& scene, const SceneEdits& edits) const {
    return guarded([&] {
        const PreparedImpl& base = requirePrepared(scene);
        const pn::Scene& s = base.prepared.scene();
        pn::SceneEdits e;
        auto index = [](std::size_t i, const char* what) {
            require(i < UINT32_MAX, std::string("edit: ") + what + " " + std::to_string(i) + " does not exist");
            return static_cast<std::uint32_t>(i);
        };
        for (const auto& [i, m] : edits.transforms) e.transforms.emplace_back(index(i, "instance"), in(m));
        for (const auto& [id, m] : edits.materials) {
            // An edit can name only textures the prepared scene read already.
            const auto known = [&, id = id](std::string& path, pn::TextureColorSpace space) {
                for (size_t i = 0; i < s.textures.size(); ++i)
                    if (s.textures[i].name == path && s.textures[i].colorSpace == space) return int(i);
                fail(ErrorCode::InvalidArgument, "edit: material " + std::to_string(id) + ": its texture '" + path +
                                                     "' is not one the prepared scene read: prepare the edited scene instead");
            };
            e.materials.emplace_back(id, checkedMaterial(m, known));
        }
        for (const auto& [i, c] : edits.pointLights) e.pointLights.emplace_back(index(i, "point light"), in(c));
        for (const auto& [i, c] : edits.directionalLights)
            e.directionalLights.emplace_back(index(i, "directional light"), in(c));
        e.environmentRotateDegrees = edits.environmentRotateDegrees;
        e.environmentScale = edits.environmentScale;
        PreparedScene p;
        Access::set(p, std::make_shared<const PreparedImpl>(base, e, impl_->log));
        return p;
    });
}

}  // namespace pnb
