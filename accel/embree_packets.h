// Embree's 4/8/16-wide packet types and entry points by width, so one loop
// serves all three (used by the Embree accelerator and the raw benchmark harness).
#pragma once

#include <embree3/rtcore.h>

#include "core/ray.h"

namespace penumbra {

// Embree's packet types and entry points by width, so one loop serves all three.
template <int W>
struct Packet;
template <>
struct Packet<4> {
    using RayHit = RTCRayHit4;
    using RayOnly = RTCRay4;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect4(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded4(v, s, c, r); }
};
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    using RayOnly = RTCRay8;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect8(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded8(v, s, c, r); }
};
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    using RayOnly = RTCRay16;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect16(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded16(v, s, c, r); }
};

// Writes ray r into lane `lane` of an SOA packet (RTCRayN layouts share field names).
template <class PacketRay>
inline void setLane(PacketRay& p, int lane, const Ray& r) {
    p.org_x[lane] = r.o.x;
    p.org_y[lane] = r.o.y;
    p.org_z[lane] = r.o.z;
    p.tnear[lane] = r.tnear;
    p.dir_x[lane] = r.d.x;
    p.dir_y[lane] = r.d.y;
    p.dir_z[lane] = r.d.z;
    p.time[lane] = 0.f;
    p.tfar[lane] = r.tfar;
    p.mask[lane] = ~0u;
    p.id[lane] = static_cast<unsigned>(lane);
    p.flags[lane] = 0;
}

}  // namespace penumbra
