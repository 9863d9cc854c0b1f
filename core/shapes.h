// Analytic shapes: plain data, exact intersection and uniform area sampling.
// These routines know nothing of Embree; the Embree user geometries and the
// naive accelerator call the very same functions, so they cannot drift apart.
//
// Intersections report t in the half-open interval (ray.tnear, ray.tfar], the
// interval Embree's own triangle test uses.
#pragma once

#include <cstdint>
#include <optional>

#include "core/hit.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "core/transform.h"

namespace penumbra {

/// The parametric result of a shape test: distance and two surface
/// coordinates whose meaning depends on the shape (documented per shape).
struct PrimHit {
    float t;
    float u, v;
};

/// Sphere; front side faces outwards. Hit (u, v) unused (computed from the point).
struct Sphere {
    Vec3f center;
    float radius = 1.f;
    uint32_t material = 0;
};

/// Infinite plane through point with unit normal; front = the side the normal faces.
/// A one-sided plane is invisible from behind (rays from its back pass through).
/// Hit (u, v) unused.
struct Plane {
    Vec3f point;
    Vec3f normal{0.f, 1.f, 0.f};
    bool twoSided = true;
    uint32_t material = 0;
};

/// Box: axis-aligned [lo, hi] in object space, placed by worldFromObject
/// (identity for an axis-aligned box). Faces face outwards. Hit (u, v) unused.
struct Box {
    Vec3f lo{-1.f, -1.f, -1.f};
    Vec3f hi{1.f, 1.f, 1.f};
    Transform worldFromObject;
    Transform objectFromWorld;  // kept in sync by makeBox()
    uint32_t material = 0;
    bool identity = true;       // worldFromObject is the identity (set by makeBox): hits skip the transforms
};
Box makeBox(const Vec3f& lo, const Vec3f& hi, const Transform& worldFromObject = Transform(), uint32_t material = 0);

/// Parallelogram p0 + s*a + t*b, s,t in [0,1] (a scene file's "rectangle").
/// Front side faces cross(a, b). Hit (u, v) = (s, t).
struct Rectangle {
    Vec3f p0;
    Vec3f a{1.f, 0.f, 0.f};
    Vec3f b{0.f, 0.f, 1.f};
    uint32_t material = 0;
};

/// Disk; front side faces normal. Hit (u, v) = the point's offset from the
/// centre along the disk's frame s and t axes, divided by the radius.
struct Disk {
    Vec3f center;
    Vec3f normal{0.f, 1.f, 0.f};
    float radius = 1.f;
    uint32_t material = 0;
};

/// Distance t along o + t d to sphere s within (tnear, tfar] (the nearer root
/// that lies there), or +infinity when there is none. Without branches, as
/// planeHitDistance, so that the Embree callbacks' loops over a packet's lanes
/// vectorise; intersect(Sphere, Ray) is this on one ray. The discriminant is in
/// the geometric form (Hearn & Baker; Haines et al., Ray Tracing Gems ch. 7):
/// far more accurate than b^2 - 4ac when the sphere is small relative to its
/// distance from the ray origin.
[[gnu::always_inline]] inline float sphereHitDistance(const Sphere& s, float ox, float oy, float oz, float dx, float dy, float dz,
                               float tnear, float tfar) {
    const float fx = ox - s.center.x, fy = oy - s.center.y, fz = oz - s.center.z;
    const float a = dx * dx + dy * dy + dz * dz;
    const float b = fx * dx + fy * dy + fz * dz;  // half of the usual b
    const float r2 = s.radius * s.radius;
    const float c = (fx * fx + fy * fy + fz * fz) - r2;
    const float ba = b / a;
    const float lx = fx - ba * dx, ly = fy - ba * dy, lz = fz - ba * dz;
    const float disc = a * (r2 - (lx * lx + ly * ly + lz * lz));
    const bool real = (s.radius > 0.f) & (disc >= 0.f);
    const float q = -(b + std::copysign(std::sqrt(real ? disc : 0.f), b));
    const float t0 = q == 0.f ? -b / a : q / a;
    const float t1 = q == 0.f ? -b / a : c / q;
    const float lo = t0 > t1 ? t1 : t0, hi = t0 > t1 ? t0 : t1;
    const bool loIn = (lo > tnear) & (lo <= tfar), hiIn = (hi > tnear) & (hi <= tfar);
    return !real ? kInfinity : loIn ? lo : hiIn ? hi : kInfinity;
}
/// Inline: the accelerators' sphere tests.
inline std::optional<PrimHit> intersect(const Sphere& s, const Ray& r) {
    const float t = sphereHitDistance(s, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tnear, r.tfar);
    if (t == kInfinity) return std::nullopt;
    return PrimHit{t, 0.f, 0.f};
}
/// Distance t along o + t d to plane p within (tnear, tfar], or +infinity when
/// there is none (parallel, behind a one-sided plane, outside the interval).
/// Written on the ray's components without branches, so that a loop over the
/// lanes of a ray packet vectorises; intersect(Plane, Ray) is this on one ray.
[[gnu::always_inline]] inline float planeHitDistance(const Plane& p, float ox, float oy, float oz, float dx, float dy, float dz, float tnear,
                              float tfar) {
    const Vec3f& n = p.normal;
    const float denom = dx * n.x + dy * n.y + dz * n.z;
    const float t = ((p.point.x - ox) * n.x + (p.point.y - oy) * n.y + (p.point.z - oz) * n.z) / denom;
    const bool faces = p.twoSided | (denom < 0.f);
    const bool crosses = std::fabs(denom) > 0.f, finite = std::fabs(t) < kInfinity;
    const bool hit = faces & crosses & finite & (t > tnear) & (t <= tfar);
    return hit ? t : kInfinity;
}
/// Inline: the accelerators test every plane against every ray.
inline std::optional<PrimHit> intersect(const Plane& p, const Ray& r) {
    const float t = planeHitDistance(p, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tnear, r.tfar);
    if (t == kInfinity) return std::nullopt;
    return PrimHit{t, 0.f, 0.f};
}
/// The reciprocal the slab test multiplies by: 1/d, or 1 where d is zero
/// (narrowToSlab handles that case apart). Shared by every slab of a ray.
[[gnu::always_inline]] inline float slabReciprocal(float d) { return 1.f / (d == 0.f ? 1.f : d); }
/// One slab of the box test below: narrows [enter, exit] to where o + t d
/// lies within [lo, hi] on one axis (inv = slabReciprocal(d)); a direction
/// component of zero leaves no limit when o lies within and empties the
/// interval otherwise.
[[gnu::always_inline]] inline void narrowToSlab(float lo, float hi, float o, float d, float inv, float& enter,
                                                float& exit) {
    const bool parallel = d == 0.f;
    const float tn = (lo - o) * inv, tf = (hi - o) * inv;
    // Parallel: no limit from within, an empty interval from outside (selects of floats only, so that loops vectorise).
    const float outside = (o < lo) | (o > hi) ? kInfinity : -kInfinity;
    const float near = parallel ? outside : (tn > tf ? tf : tn);
    const float far = parallel ? -outside : (tn > tf ? tn : tf);
    enter = enter < near ? near : enter;
    exit = far < exit ? far : exit;
}
/// The slab test of boxHitDistance for a ray given in the box's object
/// space, with its direction's slabReciprocal components (ix, iy, iz).
[[gnu::always_inline]] inline float boxHitDistanceInObjectSpace(const Box& b, float ox, float oy, float oz, float dx,
                                                                float dy, float dz, float ix, float iy, float iz,
                                                                float tnear, float tfar) {
    float enter = -kInfinity, exit = kInfinity;
    narrowToSlab(b.lo.x, b.hi.x, ox, dx, ix, enter, exit);
    narrowToSlab(b.lo.y, b.hi.y, oy, dy, iy, enter, exit);
    narrowToSlab(b.lo.z, b.hi.z, oz, dz, iz, enter, exit);
    const bool proper = !(b.lo.x > b.hi.x) & !(b.lo.y > b.hi.y) & !(b.lo.z > b.hi.z);
    const bool meets = proper & !(enter > exit);
    const bool enterIn = (enter > tnear) & (enter <= tfar), exitIn = (exit > tnear) & (exit <= tfar);
    return !meets ? kInfinity : enterIn ? enter : exitIn ? exit : kInfinity;
}
/// boxHitDistance for a box that is not axis-aligned: the ray taken into
/// the box's object space first (the direction transformed but not
/// normalised, so that t is the same parameter in both spaces).
[[gnu::always_inline]] inline float boxHitDistanceTransformed(const Box& b, float ox, float oy, float oz, float dx,
                                                              float dy, float dz, float tnear, float tfar) {
    const Vec3f o = b.objectFromWorld.applyPoint({ox, oy, oz});
    const Vec3f d = b.objectFromWorld.applyVector({dx, dy, dz});
    return boxHitDistanceInObjectSpace(b, o.x, o.y, o.z, d.x, d.y, d.z, slabReciprocal(d.x), slabReciprocal(d.y),
                                       slabReciprocal(d.z), tnear, tfar);
}
/// Distance t along o + t d to box b within (tnear, tfar] (where the ray
/// enters the box, or else where it leaves it), or +infinity when there is
/// none: the slab test in the box's object space (an axis-aligned box's is
/// world space: its identity transform would change no finite value).
/// Without branches within each form, as sphereHitDistance, so that a loop
/// over a packet's lanes vectorises; intersect(Box, Ray) is this on one ray.
[[gnu::always_inline]] inline float boxHitDistance(const Box& b, float ox, float oy, float oz, float dx, float dy,
                                                   float dz, float tnear, float tfar) {
    if (!b.identity) return boxHitDistanceTransformed(b, ox, oy, oz, dx, dy, dz, tnear, tfar);
    return boxHitDistanceInObjectSpace(b, ox, oy, oz, dx, dy, dz, slabReciprocal(dx), slabReciprocal(dy),
                                       slabReciprocal(dz), tnear, tfar);
}
/// Inline: the accelerators' box tests.
inline std::optional<PrimHit> intersect(const Box& b, const Ray& r) {
    const float t = boxHitDistance(b, r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tnear, r.tfar);
    if (t == kInfinity) return std::nullopt;
    return PrimHit{t, 0.f, 0.f};
}
std::optional<PrimHit> intersect(const Rectangle& q, const Ray& r);
std::optional<PrimHit> intersect(const Disk& d, const Ray& r);

/// Hit completion, beside each intersection test: writes the surface data
/// (point, normals, uv, material) of a hit at distance t with the test's
/// (u, v) into h, every one of those fields, in place (a Hit returned by
/// value and copied on is read back before its stores have retired, which
/// stalls the renderer's hot loop). Points come from the surface's own
/// parametrisation (see core/ray.h), not from o + t d. Scene::completeHit
/// dispatches to these and sets t and ref.
///
/// withUv: whether to compute the uv of a sphere, plane or box (else (0, 0)):
/// only a textured material reads it, and it costs a sphere two inverse
/// trigonometric functions, a plane its tangent frame, a box two divisions
/// (the gain: docs/benchmarks.md, "Texture coordinates only where a texture
/// reads them"). The others' uv is a copy or an interpolation, always made.
void completeHit(const Sphere& s, const Ray& r, float t, Hit& h, bool withUv = true);
/// (Inline: the ground plane's hits are most of some scenes' camera hits.)
inline void completeHit(const Plane& pl, const Ray& ray, float t, Hit& h, bool withUv = true) {
    const Vec3f p = ray.o + t * ray.d;
    h.p = p - dot(p - pl.point, pl.normal) * pl.normal;
    h.ng = h.ns = pl.normal;
    h.uv = {};
    if (withUv) {
        const Frame f = Frame::fromNormal(pl.normal);
        const Vec3f d = h.p - pl.point;
        h.uv = {dot(d, f.s), dot(d, f.t)};
    }
    h.material = pl.material;
}
void completeHit(const Box& b, const Ray& r, float t, Hit& h, bool withUv = true);
void completeHit(const Rectangle& q, float u, float v, Hit& h);
void completeHit(const Disk& d, float u, float v, Hit& h);

/// The directions in which completeHit's uv grows at a point of the shape:
/// dp/du and dp/dv (any lengths), the tangent frame of normal and bump maps.
struct UvDerivatives {
    Vec3f dpdu, dpdv;
};
/// p: the hit point (off the poles, where u turns about the y axis).
UvDerivatives uvDerivatives(const Sphere& s, const Vec3f& p);
/// ng: the hit's geometric normal, which names the face.
UvDerivatives uvDerivatives(const Box& b, const Vec3f& ng);
inline UvDerivatives uvDerivatives(const Rectangle& q) { return {q.a, q.b}; }
inline UvDerivatives uvDerivatives(const Plane& pl) {
    const Frame f = Frame::fromNormal(pl.normal);
    return {f.s, f.t};
}
inline UvDerivatives uvDerivatives(const Disk& d) {
    const Frame f = Frame::fromNormal(d.normal);
    return {f.s, f.t};
}
/// One triangle's corners: positions, and (optional, else null) 3 vertex normals and 3 UVs.
struct TriangleCorners {
    Vec3f p[3];
    const Vec3f* n = nullptr;
    const Vec2f* uv = nullptr;
};
/// What a triangle hit at barycentrics (1-u-v, u, v) holds: the interpolated
/// point, the unit geometric normal, the shading normal (the vertex normals
/// interpolated and turned to ng's side; ng where there are none or they
/// cancel) and the uv (the vertices', else (u, v)).
struct TriangleHitValues {
    Vec3f p, ng, ns;
    Vec2f uv;
};
/// The rule every triangle hit follows, one lane's worth: inline and free of
/// branches that depend on the lane, so that completeTriangleHitLanes' loop
/// over lanes vectorises it (sqrt and division round as the scalar ones do).
[[gnu::always_inline]] inline TriangleHitValues triangleHitValues(const TriangleCorners& c, float u, float v) {
    // The choices component by component, as normalize() makes its own: selects
    // of whole vectors kept GCC from vectorising the loop over lanes.
    TriangleHitValues r;
    const float w = 1.f - u - v;
    r.p = w * c.p[0] + u * c.p[1] + v * c.p[2];
    r.ng = normalize(cross(c.p[1] - c.p[0], c.p[2] - c.p[0]));
    r.ns = r.ng;
    if (c.n) {
        const Vec3f n = normalize(w * c.n[0] + u * c.n[1] + v * c.n[2]);
        const bool use = lengthSquared(n) > 0.f, flip = dot(n, r.ng) < 0.f;
        r.ns.x = use ? (flip ? -n.x : n.x) : r.ng.x;
        r.ns.y = use ? (flip ? -n.y : n.y) : r.ng.y;
        r.ns.z = use ? (flip ? -n.z : n.z) : r.ng.z;
    }
    r.uv = c.uv ? Vec2f{w * c.uv[0].x + u * c.uv[1].x + v * c.uv[2].x, w * c.uv[0].y + u * c.uv[1].y + v * c.uv[2].y}
                : Vec2f{u, v};
    return r;
}
/// The hit at barycentrics (1-u-v, u, v) of a triangle given by its corners
/// (what the mesh version computes; the material is left as it was).
void completeTriangleHit(const TriangleCorners& corners, float u, float v, Hit& h);
/// Triangle `tri` of a mesh at barycentrics (u, v): interpolated point, smooth
/// normal (when the mesh has normals), uv and material.
void completeTriangleHit(const TriangleMesh& m, uint32_t tri, float u, float v, Hit& h);
/// completeTriangleHit(m, tri[l], u[l], v[l], *out[l]) for the n <= 16 lanes
/// of a batch whose hits lie on one mesh, the same values bit for bit: the
/// corners gathered into arrays and triangleHitValues over the lanes at once,
/// where one by one each hit waited on its own square roots and divisions.
void completeTriangleHitLanes(const TriangleMesh& m, int n, const uint32_t* tri, const float* u, const float* v,
                              Hit* const* out);

/// Watertight ray/triangle test (Woop, Benthin & Wald 2013): rays through a
/// shared edge or vertex hit at least one of the triangles sharing it.
/// (u, v) are the barycentrics of p1 and p2: p = (1-u-v) p0 + u p1 + v p2.
std::optional<PrimHit> intersectTriangle(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, const Ray& r);

/// World-space bounds (finite shapes only).
Bounds3f bounds(const Sphere& s);
Bounds3f bounds(const Box& b);
Bounds3f bounds(const Rectangle& q);
Bounds3f bounds(const Disk& d);
/// Of the vertices the triangles use (a mesh may hold others).
Bounds3f bounds(const TriangleMesh& m);

float area(const Sphere& s);
float area(const Rectangle& q);
float area(const Disk& d);
float triangleArea(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2);

/// A point sampled on a surface, with its unit normal and the pdf with
/// respect to area (1 / area for uniform sampling).
struct SurfaceSample {
    Vec3f p;
    Vec3f n;
    float pdfArea;
};

SurfaceSample sampleUniform(const Sphere& s, Vec2f u);
SurfaceSample sampleUniform(const Rectangle& q, Vec2f u);
SurfaceSample sampleUniform(const Disk& d, Vec2f u);
SurfaceSample sampleTriangle(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, Vec2f u);

/// Unit normal of the front side.
inline Vec3f rectangleNormal(const Rectangle& q) { return normalize(cross(q.a, q.b)); }

}  // namespace penumbra
