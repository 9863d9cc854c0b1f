#include "lights/area_light.h"

#include <algorithm>
#include <bit>

#include "core/emission.h"
#include "core/lane_clones.h"
#include "core/sampling.h"
#include "lights/light_lanes.h"
#include "lights/spherical_cap.h"
#include "lights/spherical_rectangle.h"
#include "lights/spherical_triangle.h"

namespace penumbra {

std::optional<LightSample> areaLightSample(const Vec3f& p, const SurfaceSample& s, const Rgb& Le, bool twoSided) {
    Vec3f d = s.p - p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f) || !(s.pdfArea > 0.f)) return std::nullopt;
    float dist = std::sqrt(dist2);
    Vec3f wi = d / dist;
    float cosLight = -dot(s.n, wi);  // cos(theta') at the light
    if (twoSided) cosLight = std::fabs(cosLight);
    if (!(cosLight > 0.f)) return std::nullopt;
    // Area pdf to solid angle: p_w = p_A * d^2 / cos(theta').
    float pdf = s.pdfArea * dist2 / cosLight;
    if (!std::isfinite(pdf) || !(pdf > 0.f)) return std::nullopt;
    return LightSample{Le, wi, s.p, dist, pdf, false};
}

float areaPdfToSolidAngle(const Vec3f& p, const Vec3f& point, const Vec3f& n, float pdfArea, bool twoSided) {
    const Vec3f d = point - p;
    const float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f)) return 0.f;
    float cosLight = -dot(n, d) / std::sqrt(dist2);
    if (twoSided) cosLight = std::fabs(cosLight);
    if (!(cosLight > 0.f)) return 0.f;
    const float pdf = pdfArea * dist2 / cosLight;
    return std::isfinite(pdf) ? pdf : 0.f;
}

// A rectangle as the lane loops read it (copies: the loops' stores cannot change them).
struct RectangleLanes {
    Vec3f corner, edgeA, edgeB, n;
    float pdfArea;
    uint32_t signMask;  // clears the sign bit of cos(theta') where the emitter is two-sided (std::fabs)
    Rgb Le;
};

namespace {

std::optional<LightSample> solidAngleSample(const Vec3f& p, const Vec3f& point, float solidAngle, const Rgb& Le) {
    const Vec3f d = point - p;
    const float dist = length(d);
    if (!(dist > 0.f) || !(solidAngle > 0.f)) return std::nullopt;
    return LightSample{Le, d / dist, point, dist, 1.f / solidAngle, false};
}

// areaLightSample as the body of a loop over lanes: lane l's point q on the
// emitter (unit normal n, area pdf pdfArea) seen from p, into out's lane l;
// want: whether the lane asked for a sample. signMask clears the sign bit of
// cos(theta') where the emitter is two-sided (std::fabs): a select on
// twoSided would keep the loop from vectorising; the mask does not.
[[gnu::always_inline]] inline void areaSampleLane(int l, float qx, float qy, float qz, float px, float py, float pz,
                                                  float nx, float ny, float nz, float pdfArea, uint32_t signMask,
                                                  const Rgb& Le, int32_t want, LightLanes& out) {
    const float dx = qx - px, dy = qy - py, dz = qz - pz;
    const float dist2 = dx * dx + dy * dy + dz * dz;
    const float dist = std::sqrt(dist2);
    const float inv = 1.f / dist;
    const float wx = dx * inv, wy = dy * inv, wz = dz * inv;
    const float cosLight = std::bit_cast<float>(std::bit_cast<uint32_t>(-(nx * wx + ny * wy + nz * wz)) & signMask);
    const float pdf = pdfArea * dist2 / cosLight;
    const int32_t ok =
        (dist2 > 0.f) & (pdfArea > 0.f) & (cosLight > 0.f) & (std::fabs(pdf) < kInfinity) & (pdf > 0.f);
    out.ok[l] = want & ok;
    out.wx[l] = wx;
    out.wy[l] = wy;
    out.wz[l] = wz;
    out.qx[l] = qx;
    out.qy[l] = qy;
    out.qz[l] = qz;
    out.distance[l] = dist;
    out.pdf[l] = pdf;
    out.Lr[l] = Le.r;
    out.Lg[l] = Le.g;
    out.Lb[l] = Le.b;
}

constexpr uint32_t signMaskOf(bool twoSided) { return twoSided ? 0x7fffffffu : 0xffffffffu; }

// rectangleAreaSample (areaLightSample at corner + u.x edgeA + u.y edgeB) at
// each lane l < n, as one loop: the shading point of lane l is (px[l], py[l],
// pz[l]), or (px[0], py[0], pz[0]) for every lane where kOnePoint. Inlined
// into each compiled copy of its callers (core/lane_clones.h).
template <bool kOnePoint>
[[gnu::always_inline]] inline void rectangleAreaLanes(const RectangleLanes& r, const float* px, const float* py,
                                                      const float* pz, const float* ux, const float* uy,
                                                      const int32_t* want, int n, LightLanes& out) {
    const Vec3f c = r.corner, ea = r.edgeA, eb = r.edgeB, fn = r.n;
    const float pdfArea = r.pdfArea;
    const uint32_t signMask = r.signMask;
    const Rgb Le = r.Le;
    for (int l = 0; l < n; ++l) {
        const int i = kOnePoint ? 0 : l;
        const float qx = c.x + ux[l] * ea.x + uy[l] * eb.x;
        const float qy = c.y + ux[l] * ea.y + uy[l] * eb.y;
        const float qz = c.z + ux[l] * ea.z + uy[l] * eb.z;
        areaSampleLane(l, qx, qy, qz, px[i], py[i], pz[i], fn.x, fn.y, fn.z, pdfArea, signMask, Le, kOnePoint ? 1 : want[l], out);
    }
}

}  // namespace

ShapeAreaLight::ShapeAreaLight(const Scene& scene, Kind kind, uint32_t index) : scene_(scene), kind_(kind), index_(index) {
    uint32_t mat = 0;
    switch (kind) {
        case Kind::Rectangle:
            mat = scene.rectangles[index].material;
            area_ = penumbra::area(scene.rectangles[index]);
            break;
        case Kind::Disk:
            mat = scene.disks[index].material;
            area_ = penumbra::area(scene.disks[index]);
            break;
        case Kind::Sphere:
            mat = scene.spheres[index].material;
            area_ = penumbra::area(scene.spheres[index]);
            break;
    }
    Le_ = scene.materials[mat].ke;
    twoSided_ = scene.materials[mat].twoSidedEmission;
    pdfArea_ = 1.f / area_;
    if (kind == Kind::Rectangle) {
        const Rectangle& q = scene.rectangles[index];
        frame_.n = rectangleNormal(q);
        orthogonalEdges_ = std::fabs(dot(q.a, q.b)) <= 1e-5f * length(q.a) * length(q.b);
        boundCenter_ = q.p0 + 0.5f * (q.a + q.b);
        boundRadius2_ = 0.25f * std::max(lengthSquared(q.a + q.b), lengthSquared(q.a - q.b));
        corner_ = q.p0;
        edgeA_ = q.a;
        edgeB_ = q.b;
    }
    if (kind == Kind::Disk) frame_ = Frame::fromNormal(scene.disks[index].normal);
}

bool ShapeAreaLight::emitsTowards(const Vec3f& p) const {
    if (twoSided_) return true;
    switch (kind_) {
        case Kind::Rectangle: return dot(frame_.n, p - corner_) > 0.f;
        case Kind::Disk: return dot(frame_.n, p - scene_.disks[index_].center) > 0.f;
        case Kind::Sphere: return true;  // outside sees the front; inside is checked per point
    }
    return true;
}

std::optional<SphericalRectangle> ShapeAreaLight::sphericalRectangleAt(const Vec3f& p) const {
    if (!orthogonalEdges_ || !subtendsAtLeast(boundCenter_, boundRadius2_, p, kSolidAngleSamplingMinBound))
        return std::nullopt;
    const SphericalRectangle sr(p, corner_, edgeA_, edgeB_);
    if (sr.solidAngle() < kSphericalMinSolidAngle) return std::nullopt;
    return sr;
}

std::optional<LightSample> ShapeAreaLight::rectangleAreaSample(const Vec3f& p, Vec2f u) const {
    return areaLightSample(p, SurfaceSample{corner_ + u.x * edgeA_ + u.y * edgeB_, frame_.n, pdfArea_}, Le_, twoSided_);
}

std::optional<LightSample> ShapeAreaLight::sample(const Vec3f& p, Vec2f u) const {
    switch (kind_) {
        case Kind::Rectangle: {
            if (!emitsTowards(p)) break;
            if (const auto sr = sphericalRectangleAt(p)) return solidAngleSample(p, sr->sample(u), sr->solidAngle(), Le_);
            break;
        }
        case Kind::Sphere: {
            const Sphere& s = scene_.spheres[index_];
            if (auto c = sampleSphereCone(p, s.center, s.radius, u))
                return LightSample{Le_, c->wi, c->point, length(c->point - p), c->pdf, false};
            break;  // inside or on the sphere: by area
        }
        case Kind::Disk: break;
    }
    return sampleArea(p, u);
}

void ShapeAreaLight::mayReachLanes(const LanePoints& at, int n, int32_t* reach) const {
    if (kind_ == Kind::Rectangle) {
        rectangleReachLanes(at, n, reach);
    } else {
        Light::mayReachLanes(at, n, reach);
    }
}

PENUMBRA_LANE_CLONES void ShapeAreaLight::rectangleReachLanes(const LanePoints& at, int n, int32_t* reach) const {
    // mayReach's rectangle test and emitsTowards, written out on the lanes' arrays.
    const Vec3f c = corner_, ea = edgeA_, eb = edgeB_, fn = frame_.n;
    const int32_t twoSided = twoSided_ ? 1 : 0;
    for (int l = 0; l < n; ++l) {
        const float px = at.px[l], py = at.py[l], pz = at.pz[l], nx = at.nx[l], ny = at.ny[l], nz = at.nz[l];
        const float h = (c.x - px) * nx + (c.y - py) * ny + (c.z - pz) * nz;
        const float ha = ea.x * nx + ea.y * ny + ea.z * nz, hb = eb.x * nx + eb.y * ny + eb.z * nz;
        const int32_t front = fn.x * (px - c.x) + fn.y * (py - c.y) + fn.z * (pz - c.z) > 0.f;
        const float top = h + (ha < 0.f ? 0.f : ha) + (hb < 0.f ? 0.f : hb);
        reach[l] = (twoSided | front) & (top > 0.f);
    }
}

void ShapeAreaLight::sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                                 LightLanes& out) const {
    if (kind_ == Kind::Rectangle) {
        rectangleSampleLanes(at, ux, uy, want, n, out);
    } else {
        Light::sampleLanes(at, ux, uy, want, n, out);
    }
}

PENUMBRA_LANE_CLONES void ShapeAreaLight::rectangleSampleLanes(const LanePoints& at, const float* ux, const float* uy,
                                                               const int32_t* want, int n, LightLanes& out) const {
    // What sample() gives at each lane, in three passes: which points are near
    // enough for a spherical rectangle, and every lane's area sample, as loops
    // over the lanes; then the near points' spherical samples one by one (each
    // has its own set-up). Each pass computes what sample() computes, in its order.
    constexpr int W = LanePoints::kWidth;
    const Vec3f c = corner_, fn = frame_.n, bc = boundCenter_;
    const float r2 = boundRadius2_;
    const int32_t twoSided = twoSided_ ? 1 : 0;
    alignas(64) int32_t near[W];
    int anyNear = 0;
    for (int l = 0; l < n; ++l) {
        const float px = at.px[l], py = at.py[l], pz = at.pz[l];
        const int32_t front = fn.x * (px - c.x) + fn.y * (py - c.y) + fn.z * (pz - c.z) > 0.f;
        const int32_t subtends = subtendsAtLeast(bc, r2, Vec3f{px, py, pz}, kSolidAngleSamplingMinBound);
        near[l] = want[l] & (twoSided | front) & subtends & int32_t(orthogonalEdges_);
        anyNear |= near[l];
    }
    rectangleAreaLanes<false>(rectangleLanes(), at.px, at.py, at.pz, ux, uy, want, n, out);
    // The near points' spherical samples replace their area samples.
    if (!anyNear) return;
    for (int l = 0; l < n; ++l) {
        if (!near[l]) continue;
        const Vec3f p = at.p(l);
        const SphericalRectangle sr(p, corner_, edgeA_, edgeB_);
        if (sr.solidAngle() < kSphericalMinSolidAngle) continue;  // too small after all: by area
        out.set(l, solidAngleSample(p, sr.sample(Vec2f{ux[l], uy[l]}), sr.solidAngle(), Le_));
    }
}

void ShapeAreaLight::sampleManyLanes(const Vec3f& p, const float* ux, const float* uy, int n, LightLanes& out) const {
    if (kind_ == Kind::Rectangle) {
        rectangleSampleManyLanes(p, ux, uy, n, out);
    } else {
        Light::sampleManyLanes(p, ux, uy, n, out);
    }
}

PENUMBRA_LANE_CLONES void ShapeAreaLight::rectangleSampleManyLanes(const Vec3f& p, const float* ux, const float* uy,
                                                                   int n, LightLanes& out) const {
    // sampleMany's decision, taken once for p; the area samples as one loop.
    if (const auto sr = emitsTowards(p) ? sphericalRectangleAt(p) : std::nullopt) {
        for (int l = 0; l < n; ++l)
            out.set(l, solidAngleSample(p, sr->sample(Vec2f{ux[l], uy[l]}), sr->solidAngle(), Le_));
        return;
    }
    rectangleAreaLanes<true>(rectangleLanes(), &p.x, &p.y, &p.z, ux, uy, nullptr, n, out);
}

RectangleLanes ShapeAreaLight::rectangleLanes() const {
    return RectangleLanes{corner_, edgeA_, edgeB_, frame_.n, pdfArea_, signMaskOf(twoSided_), Le_};
}

void ShapeAreaLight::sampleMany(const Vec3f& p, std::span<const Vec2f> u,
                                std::span<std::optional<LightSample>> out) const {
    if (kind_ != Kind::Rectangle) {
        Light::sampleMany(p, u, out);
        return;
    }
    // What sample() gives for each u from this p, with its decision taken once.
    // One spherical rectangle (its set-up is most of a sample's cost) for all of p's samples.
    if (const auto sr = emitsTowards(p) ? sphericalRectangleAt(p) : std::nullopt) {
        for (size_t k = 0; k < u.size(); ++k) out[k] = solidAngleSample(p, sr->sample(u[k]), sr->solidAngle(), Le_);
        return;
    }
    // By area: one loop without calls.
    for (size_t k = 0; k < u.size(); ++k) out[k] = rectangleAreaSample(p, u[k]);
}

float ShapeAreaLight::pdf(const Vec3f& p, const Hit& onLight) const {
    if (!emitsTowards(p)) return 0.f;
    if (kind_ == Kind::Rectangle)
        if (const auto sr = sphericalRectangleAt(p)) return 1.f / sr->solidAngle();
    if (kind_ == Kind::Sphere) {
        const Sphere& s = scene_.spheres[index_];
        if (const float pdf = sphereConePdf(p, s.center, s.radius); pdf > 0.f) return pdf;
    }
    return areaPdfToSolidAngle(p, onLight.p, onLight.ng, pdfArea_, twoSided_);
}

std::optional<LightSample> ShapeAreaLight::sampleArea(const Vec3f& p, Vec2f u) const {
    // The same points as sampleUniform(shape, u), with the normal, frame and
    // pdf taken from the constructor.
    SurfaceSample s{};
    switch (kind_) {
        case Kind::Rectangle: return rectangleAreaSample(p, u);
        case Kind::Disk: {
            const Disk& d = scene_.disks[index_];
            const Vec2f c = squareToConcentricDisk(u);
            s = {d.center + d.radius * (c.x * frame_.s + c.y * frame_.t), d.normal, pdfArea_};
            break;
        }
        case Kind::Sphere: s = sampleUniform(scene_.spheres[index_], u); break;
    }
    return areaLightSample(p, s, Le_, twoSided_);
}

bool ShapeAreaLight::mayReach(const Vec3f& p, const Vec3f& n) const {
    // The highest point of the shape over the plane (p, n): the shapes are
    // convex, so a sample above the plane exists only if that point is above it.
    switch (kind_) {
        case Kind::Rectangle: {
            const float h = dot(corner_ - p, n), ha = dot(edgeA_, n), hb = dot(edgeB_, n);
            return emitsTowards(p) && h + std::max(ha, 0.f) + std::max(hb, 0.f) > 0.f;
        }
        case Kind::Disk: {
            if (!emitsTowards(p)) return false;
            const Disk& d = scene_.disks[index_];
            const float c = dot(n, d.normal);
            return dot(d.center - p, n) + d.radius * std::sqrt(std::max(0.f, 1.f - c * c)) > 0.f;
        }
        case Kind::Sphere: {
            const Sphere& s = scene_.spheres[index_];
            return dot(s.center - p, n) + s.radius > 0.f;
        }
    }
    return true;
}

double ShapeAreaLight::power() const { return channelMean(Le_) * double(area_) * kPi * (twoSided_ ? 2.0 : 1.0); }

std::optional<LightBounds> ShapeAreaLight::bounds() const {
    // Flat emitters send light into the half space their normal faces (both,
    // where two-sided); a sphere's surface faces every way.
    LightBounds b;
    b.twoSided = twoSided_;
    switch (kind_) {
        case Kind::Rectangle:
            b.box = penumbra::bounds(scene_.rectangles[index_]);
            b.axis = frame_.n;
            b.cosThetaO = 1.f;
            break;
        case Kind::Disk:
            b.box = penumbra::bounds(scene_.disks[index_]);
            b.axis = frame_.n;
            b.cosThetaO = 1.f;
            break;
        case Kind::Sphere: b.box = penumbra::bounds(scene_.spheres[index_]); break;
    }
    return b;
}

MeshAreaLight::MeshAreaLight(const Scene& scene, uint32_t mesh, uint32_t material, std::vector<uint32_t> triangles,
                             const TextureCache* textures) {
    Le_ = scene.materials[material].ke;
    meanLe_ = Le_;
    if (texturedEmission(scene.materials[material], textures) && !scene.meshes[mesh].uvs.empty()) {
        material_ = &scene.materials[material];
        mesh_ = &scene.meshes[mesh];
        textures_ = textures;
        meanLe_ = meanEmittedRadiance(*material_, textures);
    }
    twoSided_ = scene.materials[material].twoSidedEmission;
    const TriangleMesh& m = scene.meshes[mesh];
    std::sort(triangles.begin(), triangles.end());
    triangles_.reserve(triangles.size());
    cdf_.reserve(triangles.size());
    double acc = 0.0;
    for (uint32_t t : triangles) {
        Vec3f p0, p1, p2;
        m.vertices(t, p0, p1, p2);
        const Vec3f e1 = p1 - p0, e2 = p2 - p0;
        const Vec3f c = (p0 + p1 + p2) / 3.f;
        const float r2 = std::max({lengthSquared(p0 - c), lengthSquared(p1 - c), lengthSquared(p2 - c)});
        triangles_.push_back(Triangle{p0, e1, e2, normalize(cross(e1, e2)), c, r2});
        acc += penumbra::triangleArea(p0, p1, p2);
        cdf_.push_back(static_cast<float>(acc));
    }
    meshTriangles_ = std::move(triangles);
    totalArea_ = static_cast<float>(acc);
    Bounds3f b;
    for (const Triangle& t : triangles_) {
        b.extend(t.p0);
        b.extend(t.p0 + t.e1);
        b.extend(t.p0 + t.e2);
    }
    if (!triangles_.empty()) {
        boundCenter_ = b.center();
        boundRadius2_ = 0.25f * lengthSquared(b.diagonal());
    }
}

size_t MeshAreaLight::pick(Vec2f& u) const {
    // Pick a triangle in proportion to its area with u.x, then reuse the
    // remainder of u.x inside the chosen triangle so the sample set stays stratified.
    const float target = u.x * totalArea_;
    size_t i = triangles_.size() == 1 ? 0 : size_t(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin());
    i = std::min(i, cdf_.size() - 1);
    const float lo = i ? cdf_[i - 1] : 0.f;
    const float triArea = cdf_[i] - lo;
    u.x = triArea > 0.f ? std::clamp((target - lo) / triArea, 0.f, 0x1.fffffep-1f) : 0.5f;
    return i;
}

float MeshAreaLight::sphericalSolidAngle(size_t i, const Vec3f& p) const {
    const Triangle& t = triangles_[i];
    const Vec3f p1 = t.p0 + t.e1, p2 = t.p0 + t.e2;
    // Cheap test first: seen from beyond twice its bounding radius, every point
    // of the triangle is at least half the distance to its centroid away, so
    // it subtends less than 4 area / d^2; small ones are sampled by area
    // without the trigonometry.
    const float d2 = lengthSquared(t.centroid - p);
    if (d2 > 4.f * t.radius2 && 4.f * triangleArea(i) < kSphericalMinSolidAngle * d2) return 0.f;
    const float omega = triangleSolidAngle(p, t.p0, p1, p2);
    return omega >= kSphericalMinSolidAngle ? omega : 0.f;
}

float MeshAreaLight::solidAngles(const Vec3f& p, float* omegas) const {
    float total = 0.f;
    for (size_t i = 0; i < triangles_.size(); ++i) {
        const Triangle& t = triangles_[i];
        // A point in the plane of one of the light's triangles (a shading
        // point on the light itself, on an emitter that also reflects) sees
        // that triangle and its coplanar neighbours edge-on, where the solid
        // angle formula is 0/0 on shared edges. Such points are sampled by
        // area (return 0: no solid-angle pick), in sample() and pdf() alike.
        const float h = dot(t.n, p - t.p0);
        if (std::fabs(h) <= 1e-4f * std::sqrt(triangleArea(i))) return 0.f;
        const bool emits = twoSided_ || dot(t.n, p - t.p0) > 0.f;
        omegas[i] = emits ? triangleSolidAngle(p, t.p0, t.p0 + t.e1, t.p0 + t.e2) : 0.f;
        total += omegas[i];
    }
    return total;
}

std::optional<LightSample> MeshAreaLight::sampleTriangle(size_t i, const Vec3f& p, Vec2f u, float share,
                                                         float omega) const {
    const Triangle& t = triangles_[i];
    if (!twoSided_ && !(dot(t.n, p - t.p0) > 0.f)) return std::nullopt;
    omega = omega < 0.f ? sphericalSolidAngle(i, p) : (omega >= kSphericalMinSolidAngle ? omega : 0.f);
    if (omega > 0.f) {
        const auto s = sampleSphericalTriangle(p, t.p0, t.p0 + t.e1, t.p0 + t.e2, u);
        if (!s) return std::nullopt;
        // pdf = P(triangle) / its solid angle.
        return textured(i, solidAngleSample(p, s->point, omega / share, Le_));
    }
    const Vec2f b = squareToTriangle(u);
    const SurfaceSample s{t.p0 + b.x * t.e1 + b.y * t.e2, t.n, share / triangleArea(i)};
    return textured(i, areaLightSample(p, s, Le_, twoSided_));
}

std::optional<LightSample> MeshAreaLight::textured(size_t i, std::optional<LightSample> s) const {
    if (!textures_ || !s) return s;
    // The sample's barycentrics in its triangle, then its texture coordinates.
    const Triangle& t = triangles_[i];
    const Vec3f d = s->point - t.p0;
    const float d11 = dot(t.e1, t.e1), d12 = dot(t.e1, t.e2), d22 = dot(t.e2, t.e2);
    const float dd1 = dot(d, t.e1), dd2 = dot(d, t.e2);
    const float det = d11 * d22 - d12 * d12;
    if (!(det > 0.f)) return s;
    const float b1 = std::clamp((d22 * dd1 - d12 * dd2) / det, 0.f, 1.f);
    const float b2 = std::clamp((d11 * dd2 - d12 * dd1) / det, 0.f, 1.f - b1);
    const uint32_t* idx = &mesh_->indices[3 * size_t(meshTriangles_[i])];
    const auto at = [&](const std::vector<Vec2f>& uvs) {
        if (uvs.empty()) return Vec2f{};
        const Vec2f a = uvs[idx[0]], b = uvs[idx[1]], c = uvs[idx[2]];
        const float b0 = 1.f - b1 - b2;
        return Vec2f{b0 * a.x + b1 * b.x + b2 * c.x, b0 * a.y + b1 * b.y + b2 * c.y};
    };
    const Vec2f uv0 = at(mesh_->uvs);
    s->L = emittedRadiance(*material_, textures_, uv0, mesh_->uvs1.empty() ? uv0 : at(mesh_->uvs1));
    return s;
}

float MeshAreaLight::trianglePdf(size_t i, const Vec3f& p, const Vec3f& point, float share, float omega) const {
    const Triangle& t = triangles_[i];
    if (!twoSided_ && !(dot(t.n, p - t.p0) > 0.f)) return 0.f;
    omega = omega < 0.f ? sphericalSolidAngle(i, p) : (omega >= kSphericalMinSolidAngle ? omega : 0.f);
    if (omega > 0.f) return share / omega;
    return areaPdfToSolidAngle(p, point, t.n, share / triangleArea(i), twoSided_);
}

std::optional<LightSample> MeshAreaLight::sample(const Vec3f& p, Vec2f u) const {
    if (triangles_.empty() || !(totalArea_ > 0.f)) return std::nullopt;
    if (!subtendsAtLeast(boundCenter_, boundRadius2_, p, kSolidAngleSamplingMinBound)) return sampleArea(p, u);
    if (triangles_.size() <= kSolidAnglePickMax) {
        float omegas[kSolidAnglePickMax];
        const float total = solidAngles(p, omegas);
        if (!(total > 0.f)) return sampleArea(p, u);
        // Pick by solid angle with u.x, then rescale u.x for reuse (as pick()).
        const float target = u.x * total;
        float lo = 0.f;
        size_t i = 0;
        while (i + 1 < triangles_.size() && (omegas[i] == 0.f || lo + omegas[i] <= target)) lo += omegas[i++];
        while (omegas[i] == 0.f) --i;  // target at the very top: the last triangle with a share
        u.x = std::clamp((target - lo) / omegas[i], 0.f, 0x1.fffffep-1f);
        return sampleTriangle(i, p, u, omegas[i] / total, omegas[i]);
    }
    const size_t i = pick(u);
    return sampleTriangle(i, p, u, triangleArea(i) / totalArea_, -1.f);
}

float MeshAreaLight::pdf(const Vec3f& p, const Hit& onLight) const {
    const auto it = std::lower_bound(meshTriangles_.begin(), meshTriangles_.end(), onLight.ref.prim);
    if (it == meshTriangles_.end() || *it != onLight.ref.prim) return 0.f;
    const size_t i = size_t(it - meshTriangles_.begin());
    if (!subtendsAtLeast(boundCenter_, boundRadius2_, p, kSolidAngleSamplingMinBound))
        return areaPdfToSolidAngle(p, onLight.p, triangles_[i].n, 1.f / totalArea_, twoSided_);
    if (triangles_.size() <= kSolidAnglePickMax) {
        float omegas[kSolidAnglePickMax];
        const float total = solidAngles(p, omegas);
        if (!(total > 0.f)) return areaPdfToSolidAngle(p, onLight.p, triangles_[i].n, 1.f / totalArea_, twoSided_);
        if (!(omegas[i] > 0.f)) return 0.f;
        return trianglePdf(i, p, onLight.p, omegas[i] / total, omegas[i]);
    }
    return trianglePdf(i, p, onLight.p, triangleArea(i) / totalArea_, -1.f);
}

std::optional<LightSample> MeshAreaLight::sampleArea(const Vec3f& p, Vec2f u) const {
    if (triangles_.empty() || !(totalArea_ > 0.f)) return std::nullopt;
    const size_t i = pick(u);
    const Triangle& t = triangles_[i];
    const Vec2f b = squareToTriangle(u);
    const SurfaceSample s{t.p0 + b.x * t.e1 + b.y * t.e2, t.n, 1.f / totalArea_};
    return textured(i, areaLightSample(p, s, Le_, twoSided_));
}

bool MeshAreaLight::mayReach(const Vec3f& p, const Vec3f& n) const {
    return dot(boundCenter_ - p, n) + std::sqrt(boundRadius2_) > 0.f;
}

void MeshAreaLight::mayReachLanes(const LanePoints& at, int n, int32_t* reach) const { reachLanes(at, n, reach); }

PENUMBRA_LANE_CLONES void MeshAreaLight::reachLanes(const LanePoints& at, int n, int32_t* reach) const {
    // mayReach on the lanes' arrays.
    const Vec3f c = boundCenter_;
    const float r = std::sqrt(boundRadius2_);
    for (int l = 0; l < n; ++l)
        reach[l] = (c.x - at.px[l]) * at.nx[l] + (c.y - at.py[l]) * at.ny[l] + (c.z - at.pz[l]) * at.nz[l] + r > 0.f;
}

void MeshAreaLight::sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                                LightLanes& out) const {
    if (triangles_.size() <= kSolidAnglePickMax && !textures_) {
        smallMeshSampleLanes(at, ux, uy, want, n, out);
    } else {
        Light::sampleLanes(at, ux, uy, want, n, out);
    }
}

PENUMBRA_LANE_CLONES void MeshAreaLight::smallMeshSampleLanes(const LanePoints& at, const float* ux, const float* uy,
                                                              const int32_t* want, int n, LightLanes& out) const {
    // What sample() gives at each lane, in passes: which points are near
    // enough for solid-angle sampling, and every lane's area sample (pick()
    // and sampleArea()), as loops over the lanes; then the near points'
    // samples one by one through sample() (each has its own solid angles).
    // The picked triangle's data is selected triangle by triangle, which a
    // loop over lanes does without gathers: lights this small have few.
    constexpr int W = LanePoints::kWidth;
    if (triangles_.empty() || !(totalArea_ > 0.f)) {
        for (int l = 0; l < n; ++l) out.ok[l] = 0;
        return;
    }
    const int count = int(triangles_.size());
    const Vec3f bc = boundCenter_;
    const float r2 = boundRadius2_, total = totalArea_;
    alignas(64) int32_t near[W], pick[W];
    alignas(64) float target[W];
    int anyNear = 0;
    for (int l = 0; l < W; ++l) {
        target[l] = 0.f;  // lanes past n: any triangle, never read back
        pick[l] = 0;
    }
    for (int l = 0; l < n; ++l) {
        const Vec3f p{at.px[l], at.py[l], at.pz[l]};
        near[l] = want[l] & int32_t(subtendsAtLeast(bc, r2, p, kSolidAngleSamplingMinBound));
        anyNear |= near[l];
        target[l] = ux[l] * total;
    }
    // pick(): the first triangle whose cumulative area exceeds the target (upper_bound), the last at most.
    for (int j = 0; j < count; ++j) {
        const float c = cdf_[j];
        for (int l = 0; l < n; ++l) pick[l] += int32_t(c <= target[l]);
    }
    alignas(64) float p0x[W], p0y[W], p0z[W], e1x[W], e1y[W], e1z[W], e2x[W], e2y[W], e2z[W];
    alignas(64) float nx[W], ny[W], nz[W], lo[W], span[W];
    for (int j = 0; j < count; ++j) {
        const Triangle& t = triangles_[size_t(j)];
        const float tlo = j ? cdf_[size_t(j) - 1] : 0.f, tspan = cdf_[size_t(j)] - tlo;
        const bool last = j == count - 1;
        for (int l = 0; l < n; ++l) {
            const bool take = j == 0 || pick[l] == j || (last && pick[l] > j);
            p0x[l] = take ? t.p0.x : p0x[l];
            p0y[l] = take ? t.p0.y : p0y[l];
            p0z[l] = take ? t.p0.z : p0z[l];
            e1x[l] = take ? t.e1.x : e1x[l];
            e1y[l] = take ? t.e1.y : e1y[l];
            e1z[l] = take ? t.e1.z : e1z[l];
            e2x[l] = take ? t.e2.x : e2x[l];
            e2y[l] = take ? t.e2.y : e2y[l];
            e2z[l] = take ? t.e2.z : e2z[l];
            nx[l] = take ? t.n.x : nx[l];
            ny[l] = take ? t.n.y : ny[l];
            nz[l] = take ? t.n.z : nz[l];
            lo[l] = take ? tlo : lo[l];
            span[l] = take ? tspan : span[l];
        }
    }
    const float pdfArea = 1.f / totalArea_;
    const uint32_t signMask = signMaskOf(twoSided_);
    alignas(64) float su[W];
    for (int l = 0; l < n; ++l) {
        // pick()'s reuse of u.x inside the triangle, then squareToTriangle.
        const float triArea = span[l];
        const float r = (target[l] - lo[l]) / triArea;
        const float rescaled = triArea > 0.f ? (r < 0.f ? 0.f : (0x1.fffffep-1f < r ? 0x1.fffffep-1f : r)) : 0.5f;
        su[l] = std::sqrt(rescaled);
    }
    // out never shares memory with at, ux, uy or want (the callers' packets
    // and scratch arrays): without ivdep GCC tries to version this loop for
    // aliasing and, in the AVX copies, gives up and leaves it scalar.
#pragma GCC ivdep
    for (int l = 0; l < n; ++l) {
        const float bx = 1.f - su[l], by = uy[l] * su[l];
        const float qx = p0x[l] + bx * e1x[l] + by * e2x[l];
        const float qy = p0y[l] + bx * e1y[l] + by * e2y[l];
        const float qz = p0z[l] + bx * e1z[l] + by * e2z[l];
        areaSampleLane(l, qx, qy, qz, at.px[l], at.py[l], at.pz[l], nx[l], ny[l], nz[l], pdfArea, signMask, Le_,
                       want[l], out);
    }
    // The near points' samples replace their area samples.
    if (!anyNear) return;
    for (int l = 0; l < n; ++l)
        if (near[l]) out.set(l, sample(at.p(l), Vec2f{ux[l], uy[l]}));
}

double MeshAreaLight::power() const { return channelMean(meanLe_) * double(totalArea_) * kPi * (twoSided_ ? 2.0 : 1.0); }

std::optional<LightBounds> MeshAreaLight::bounds() const {
    // The cone about the triangles' mean normal through the farthest normal
    // (every direction where the normals cancel out).
    LightBounds b;
    b.twoSided = twoSided_;
    Vec3f sum;
    for (const Triangle& t : triangles_) {
        b.box.extend(t.p0);
        b.box.extend(t.p0 + t.e1);
        b.box.extend(t.p0 + t.e2);
        sum += t.n;
    }
    const Vec3f axis = normalize(sum);
    if (!(lengthSquared(axis) > 0.f)) return b;  // the default cone: every direction
    b.axis = axis;
    b.cosThetaO = 1.f;
    for (const Triangle& t : triangles_) b.cosThetaO = std::min(b.cosThetaO, dot(b.axis, t.n));
    // Rounding in the dot products must not leave a normal outside.
    if (b.cosThetaO < 1.f) b.cosThetaO = std::max(-1.f, b.cosThetaO - 1e-5f);
    return b;
}

}  // namespace penumbra
