#include "core/shapes.h"

#include <cassert>

#include "core/lane_clones.h"
#include "core/sampling.h"

namespace penumbra {
namespace {

inline bool inRange(float t, const Ray& r) { return t > r.tnear && t <= r.tfar; }

// Hit of a ray with the plane dot(x - p, n) = 0; nullopt when (nearly) parallel.
inline std::optional<float> planeT(const Vec3f& p, const Vec3f& n, const Ray& r) {
    float denom = dot(r.d, n);
    if (!(std::fabs(denom) > 0.f)) return std::nullopt;
    float t = dot(p - r.o, n) / denom;
    if (!std::isfinite(t)) return std::nullopt;
    return t;
}

}  // namespace

Box makeBox(const Vec3f& lo, const Vec3f& hi, const Transform& worldFromObject, uint32_t material) {
    Box b;
    b.lo = lo;
    b.hi = hi;
    b.worldFromObject = worldFromObject;
    b.identity = worldFromObject.isIdentity();
    if (!worldFromObject.inverse(b.objectFromWorld)) {
        // A singular transform flattens the box to nothing visible; an
        // inverted (empty) slab makes every test miss instead of producing NaN.
        b.lo = Vec3f(1.f);
        b.hi = Vec3f(-1.f);
    }
    b.material = material;
    return b;
}

void completeHit(const Sphere& s, const Ray& ray, float t, Hit& h, bool withUv) {
    const Vec3f n = normalize(ray.o + t * ray.d - s.center);
    // Re-project onto the surface: the error is then relative to the
    // sphere's own coordinates, not to the distance travelled.
    h.p = s.center + s.radius * n;
    h.ng = h.ns = n;
    h.uv = withUv ? Vec2f{std::atan2(n.z, n.x) * kInv2Pi + 0.5f, std::acos(std::clamp(n.y, -1.f, 1.f)) * kInvPi}
                  : Vec2f{};
    h.material = s.material;
}

UvDerivatives uvDerivatives(const Sphere& s, const Vec3f& p) {
    // u = phi / 2 pi + 1/2 with phi = atan2(n.z, n.x), v = theta / pi from +y:
    // d/dphi and d/dtheta (times sin theta) of the unit normal.
    const Vec3f n = normalize(p - s.center);
    return {Vec3f{-n.z, 0.f, n.x}, Vec3f{n.y * n.x, n.y * n.y - 1.f, n.y * n.z}};
}

void completeHit(const Box& b, const Ray& ray, float t, Hit& h, bool withUv) {
    // An axis-aligned box (most are) skips the transforms: the same values,
    // up to the sign of zero components.
    Vec3f po = b.identity ? ray.o + t * ray.d
                          : b.objectFromWorld.applyPoint(ray.o) + t * b.objectFromWorld.applyVector(ray.d);
    // The face is the slab whose plane the point lies closest to (relative to
    // the box size); snap the point onto it.
    const Vec3f ext = max(b.hi - b.lo, Vec3f(1e-30f));
    int axis = 0;
    bool upper = false;
    float best = kInfinity;
    for (int i = 0; i < 3; ++i) {
        const float dl = std::fabs(po[i] - b.lo[i]) / ext[i];
        const float dh = std::fabs(po[i] - b.hi[i]) / ext[i];
        if (dl < best) { best = dl; axis = i; upper = false; }
        if (dh < best) { best = dh; axis = i; upper = true; }
    }
    po[axis] = upper ? b.hi[axis] : b.lo[axis];
    Vec3f no{};
    no[axis] = upper ? 1.f : -1.f;
    h.p = b.identity ? po : b.worldFromObject.applyPoint(po);
    h.ng = h.ns = b.identity ? no : normalize(b.worldFromObject.applyNormal(no));
    h.uv = {};
    if (withUv) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        h.uv = {(po[a1] - b.lo[a1]) / ext[a1], (po[a2] - b.lo[a2]) / ext[a2]};
    }
    h.material = b.material;
}

UvDerivatives uvDerivatives(const Box& b, const Vec3f& ng) {
    // The face's axis, as completeHit chose it; uv run along the next two axes.
    const Vec3f no = b.identity ? ng : b.objectFromWorld.applyNormal(ng);
    int axis = 0;
    for (int i = 1; i < 3; ++i)
        if (std::fabs(no[i]) > std::fabs(no[axis])) axis = i;
    Vec3f du{}, dv{};
    du[(axis + 1) % 3] = 1.f;
    dv[(axis + 2) % 3] = 1.f;
    return {b.worldFromObject.applyVector(du), b.worldFromObject.applyVector(dv)};
}

std::optional<PrimHit> intersect(const Rectangle& q, const Ray& r) {
    Vec3f n = cross(q.a, q.b);
    float nn = dot(n, n);
    if (!(nn > 0.f)) return std::nullopt;
    auto t = planeT(q.p0, n, r);
    if (!t || !inRange(*t, r)) return std::nullopt;
    Vec3f d = (r.o + *t * r.d) - q.p0;
    // Coordinates in the (a, b) basis; exact for parallelograms, not only rectangles.
    float s = dot(cross(d, q.b), n) / nn;
    float u = dot(cross(q.a, d), n) / nn;
    if (s < 0.f || s > 1.f || u < 0.f || u > 1.f) return std::nullopt;
    return PrimHit{*t, s, u};
}

void completeHit(const Rectangle& q, float u, float v, Hit& h) {
    h.p = q.p0 + u * q.a + v * q.b;
    h.ng = h.ns = rectangleNormal(q);
    h.uv = {u, v};
    h.material = q.material;
}

std::optional<PrimHit> intersect(const Disk& k, const Ray& r) {
    if (!(k.radius > 0.f)) return std::nullopt;
    auto t = planeT(k.center, k.normal, r);
    if (!t || !inRange(*t, r)) return std::nullopt;
    Vec3f d = (r.o + *t * r.d) - k.center;
    if (dot(d, d) > k.radius * k.radius) return std::nullopt;
    Frame f = Frame::fromNormal(k.normal);
    return PrimHit{*t, dot(d, f.s) / k.radius, dot(d, f.t) / k.radius};
}

void completeHit(const Disk& d, float u, float v, Hit& h) {
    const Frame f = Frame::fromNormal(d.normal);
    h.p = d.center + d.radius * (u * f.s + v * f.t);
    h.ng = h.ns = d.normal;
    h.uv = {0.5f + 0.5f * u, 0.5f + 0.5f * v};
    h.material = d.material;
}

std::optional<PrimHit> intersectTriangle(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, const Ray& r) {
    // Watertight test: translate to the ray origin, permute so that z is the
    // dominant direction axis, shear so the ray is +z, then evaluate the 2D
    // edge functions (falling back to double where they are exactly zero).
    Vec3f a0 = p0 - r.o, a1 = p1 - r.o, a2 = p2 - r.o;
    int kz = maxDimension(abs(r.d));
    int kx = kz + 1 == 3 ? 0 : kz + 1;
    int ky = kx + 1 == 3 ? 0 : kx + 1;
    Vec3f d{r.d[kx], r.d[ky], r.d[kz]};
    a0 = {a0[kx], a0[ky], a0[kz]};
    a1 = {a1[kx], a1[ky], a1[kz]};
    a2 = {a2[kx], a2[ky], a2[kz]};
    float sx = -d.x / d.z, sy = -d.y / d.z, sz = 1.f / d.z;
    a0.x += sx * a0.z;
    a0.y += sy * a0.z;
    a1.x += sx * a1.z;
    a1.y += sy * a1.z;
    a2.x += sx * a2.z;
    a2.y += sy * a2.z;
    float e0 = a1.x * a2.y - a1.y * a2.x;
    float e1 = a2.x * a0.y - a2.y * a0.x;
    float e2 = a0.x * a1.y - a0.y * a1.x;
    if (e0 == 0.f || e1 == 0.f || e2 == 0.f) {
        e0 = static_cast<float>(double(a1.x) * a2.y - double(a1.y) * a2.x);
        e1 = static_cast<float>(double(a2.x) * a0.y - double(a2.y) * a0.x);
        e2 = static_cast<float>(double(a0.x) * a1.y - double(a0.y) * a1.x);
    }
    if ((e0 < 0.f || e1 < 0.f || e2 < 0.f) && (e0 > 0.f || e1 > 0.f || e2 > 0.f)) return std::nullopt;
    float det = e0 + e1 + e2;
    if (det == 0.f) return std::nullopt;
    a0.z *= sz;
    a1.z *= sz;
    a2.z *= sz;
    float tScaled = e0 * a0.z + e1 * a1.z + e2 * a2.z;
    float invDet = 1.f / det;
    float t = tScaled * invDet;
    if (!std::isfinite(t) || !inRange(t, r)) return std::nullopt;
    return PrimHit{t, e1 * invDet, e2 * invDet};
}

void completeTriangleHit(const TriangleCorners& c, float u, float v, Hit& h) {
    const TriangleHitValues r = triangleHitValues(c, u, v);
    h.p = r.p;
    h.ng = r.ng;
    h.ns = r.ns;
    h.uv = r.uv;
}

void completeTriangleHit(const TriangleMesh& m, uint32_t tri, float u, float v, Hit& h) {
    const uint32_t* idx = &m.indices[3 * size_t(tri)];
    TriangleCorners c;
    Vec3f n[3];
    Vec2f uv[3];
    for (int k = 0; k < 3; ++k) {
        c.p[k] = m.positions[idx[k]];
        if (!m.normals.empty()) n[k] = m.normals[idx[k]];
        if (!m.uvs.empty()) uv[k] = m.uvs[idx[k]];
    }
    c.n = m.normals.empty() ? nullptr : n;
    c.uv = m.uvs.empty() ? nullptr : uv;
    completeTriangleHit(c, u, v, h);
    h.material = m.materialOf(tri);
}

namespace {

// A batch's triangle corners as arrays over its lanes: [corner][axis][lane].
constexpr int kHitLanes = 16;
struct CornerLanes {
    alignas(64) float p[3][3][kHitLanes];
    alignas(64) float n[3][3][kHitLanes];
    alignas(64) float uv[3][2][kHitLanes];
};

// triangleHitValues' results as arrays over the lanes.
struct HitValueLanes {
    alignas(64) float p[3][kHitLanes], ng[3][kHitLanes], ns[3][kHitLanes], uv[2][kHitLanes];
};

template <bool Normals, bool Uvs>
[[gnu::always_inline]] inline void triangleHitValuesLanes(const CornerLanes& in, const float* u, const float* v,
                                                          HitValueLanes& out) {
    for (int l = 0; l < kHitLanes; ++l) {
        TriangleCorners c;
        Vec3f n[3];
        Vec2f uv[3];
        for (int k = 0; k < 3; ++k) {
            c.p[k] = Vec3f{in.p[k][0][l], in.p[k][1][l], in.p[k][2][l]};
            n[k] = Vec3f{in.n[k][0][l], in.n[k][1][l], in.n[k][2][l]};
            uv[k] = Vec2f{in.uv[k][0][l], in.uv[k][1][l]};
        }
        c.n = Normals ? n : nullptr;
        c.uv = Uvs ? uv : nullptr;
        const TriangleHitValues r = triangleHitValues(c, u[l], v[l]);
        out.p[0][l] = r.p.x;
        out.p[1][l] = r.p.y;
        out.p[2][l] = r.p.z;
        out.ng[0][l] = r.ng.x;
        out.ng[1][l] = r.ng.y;
        out.ng[2][l] = r.ng.z;
        out.ns[0][l] = r.ns.x;
        out.ns[1][l] = r.ns.y;
        out.ns[2][l] = r.ns.z;
        out.uv[0][l] = r.uv.x;
        out.uv[1][l] = r.uv.y;
    }
}

}  // namespace

PENUMBRA_LANE_CLONES void completeTriangleHitLanes(const TriangleMesh& m, int n, const uint32_t* tri, const float* u,
                                                   const float* v, Hit* const* out) {
    assert(n >= 0 && n <= kHitLanes);
    CornerLanes in;
    alignas(64) float ul[kHitLanes], vl[kHitLanes];
    const bool normals = !m.normals.empty(), uvs = !m.uvs.empty();
    // Every lane is computed (the lanes past n repeat the first), so that the loop has no remainder.
    for (int l = 0; l < kHitLanes; ++l) {
        const int from = l < n ? l : 0;
        const uint32_t* idx = &m.indices[3 * size_t(tri[from])];
        for (int k = 0; k < 3; ++k) {
            const Vec3f& p = m.positions[idx[k]];
            in.p[k][0][l] = p.x;
            in.p[k][1][l] = p.y;
            in.p[k][2][l] = p.z;
            const Vec3f nk = normals ? m.normals[idx[k]] : Vec3f{};
            in.n[k][0][l] = nk.x;
            in.n[k][1][l] = nk.y;
            in.n[k][2][l] = nk.z;
            const Vec2f uk = uvs ? m.uvs[idx[k]] : Vec2f{};
            in.uv[k][0][l] = uk.x;
            in.uv[k][1][l] = uk.y;
        }
        ul[l] = u[from];
        vl[l] = v[from];
    }
    HitValueLanes r;
    if (normals)
        uvs ? triangleHitValuesLanes<true, true>(in, ul, vl, r) : triangleHitValuesLanes<true, false>(in, ul, vl, r);
    else
        uvs ? triangleHitValuesLanes<false, true>(in, ul, vl, r) : triangleHitValuesLanes<false, false>(in, ul, vl, r);
    for (int l = 0; l < n; ++l) {
        Hit& h = *out[l];
        h.p = Vec3f{r.p[0][l], r.p[1][l], r.p[2][l]};
        h.ng = Vec3f{r.ng[0][l], r.ng[1][l], r.ng[2][l]};
        h.ns = Vec3f{r.ns[0][l], r.ns[1][l], r.ns[2][l]};
        h.uv = Vec2f{r.uv[0][l], r.uv[1][l]};
        h.material = m.materialOf(tri[l]);
    }
}

Bounds3f bounds(const TriangleMesh& m) {
    Bounds3f b;
    for (uint32_t i : m.indices) b.extend(m.positions[i]);
    return b;
}

Bounds3f bounds(const Sphere& s) {
    Bounds3f b;
    b.extend(s.center - Vec3f(s.radius));
    b.extend(s.center + Vec3f(s.radius));
    return b;
}

Bounds3f bounds(const Box& bx) {
    Bounds3f b;
    if (bx.lo.x > bx.hi.x || bx.lo.y > bx.hi.y || bx.lo.z > bx.hi.z) return b;
    for (int i = 0; i < 8; ++i) {
        Vec3f c{(i & 1) ? bx.hi.x : bx.lo.x, (i & 2) ? bx.hi.y : bx.lo.y, (i & 4) ? bx.hi.z : bx.lo.z};
        b.extend(bx.worldFromObject.applyPoint(c));
    }
    return b;
}

Bounds3f bounds(const Rectangle& q) {
    Bounds3f b;
    b.extend(q.p0);
    b.extend(q.p0 + q.a);
    b.extend(q.p0 + q.b);
    b.extend(q.p0 + q.a + q.b);
    return b;
}

Bounds3f bounds(const Disk& d) {
    // Per axis, the disk extends r * sqrt(1 - n_i^2) from its centre.
    Vec3f n = normalize(d.normal);
    Vec3f e{d.radius * std::sqrt(std::max(0.f, 1.f - n.x * n.x)), d.radius * std::sqrt(std::max(0.f, 1.f - n.y * n.y)),
            d.radius * std::sqrt(std::max(0.f, 1.f - n.z * n.z))};
    Bounds3f b;
    b.extend(d.center - e);
    b.extend(d.center + e);
    return b;
}

float area(const Sphere& s) { return 4.f * kPi * s.radius * s.radius; }
float area(const Rectangle& q) { return length(cross(q.a, q.b)); }
float area(const Disk& d) { return kPi * d.radius * d.radius; }
float triangleArea(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2) { return 0.5f * length(cross(p1 - p0, p2 - p0)); }

SurfaceSample sampleUniform(const Sphere& s, Vec2f u) {
    Vec3f n = squareToUniformSphere(u);
    return {s.center + s.radius * n, n, 1.f / area(s)};
}

SurfaceSample sampleUniform(const Rectangle& q, Vec2f u) {
    return {q.p0 + u.x * q.a + u.y * q.b, rectangleNormal(q), 1.f / area(q)};
}

SurfaceSample sampleUniform(const Disk& d, Vec2f u) {
    Vec2f c = squareToConcentricDisk(u);
    Frame f = Frame::fromNormal(d.normal);
    return {d.center + d.radius * (c.x * f.s + c.y * f.t), d.normal, 1.f / area(d)};
}

SurfaceSample sampleTriangle(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, Vec2f u) {
    Vec2f b = squareToTriangle(u);
    Vec3f p = (1.f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
    return {p, normalize(cross(p1 - p0, p2 - p0)), 1.f / triangleArea(p0, p1, p2)};
}

}  // namespace penumbra
