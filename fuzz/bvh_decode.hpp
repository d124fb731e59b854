// bvh_decode.hpp — the byte format of bvh_fuzz: fuzzer input bytes to a scene (0 to 64
// primitives of every kind) and a ray, and a scene back to bytes (encode_scene, for the
// seed corpus). Built of the field classes of fuzz_decode.hpp (FieldReader): a copy may
// read any earlier field of any primitive, so equal, touching and coincident primitives
// (a box's corner equal to another's, a sphere centred on a box face) are one byte away.
//
//   header byte     bit 0 scalar (0 float, 1 double); bits 1-2 t range as for the other
//                   targets (0 [0, +inf)  1 (-inf, +inf)  2 [decoded, +inf)  3 [decoded,
//                   decoded]); bits 3-7 unused
//   options byte    the BVH's leaf size 1 + (b & 7) and bins 2 + (b >> 3) (2 to 33)
//   count byte      b mod 65 primitives
//   per primitive   a kind byte k: k mod 8 = 0 Aabb (lo, hi), 1 Obb (centre, the nine axes
//                   column by column, half extents), 2 Sphere (centre, radius), 3 Plane
//                   (normal, offset), 4 ConvexPolyhedron (a plane-count byte c, c mod 17
//                   planes: normal, offset each), 5 a copy of primitive (k >> 3) mod i (the
//                   i primitives before it; an Aabb of zeros when i = 0), 6 and 7 Aabb;
//                   then its fields, each one number of the classes of fuzz_decode.hpp
//   ray             origin, direction, t_min, t_max (those the t range decodes)
//   patches         while bytes remain (at most 64): a field index byte pair (16 bits,
//                   modulo the field count) and one field that overwrites it
//
// An empty input decodes to no primitives and a zero-direction (invalid) ray. The format
// is fixed: the committed corpus depends on it.
#pragma once

#include "fuzz_decode.hpp"

#include <rayproof/closest.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <variant>
#include <vector>

namespace rayproof::fuzz {

inline constexpr int kMaxScenePrims = 64;
inline constexpr int kMaxScenePlanes = 16;

enum SceneKind : unsigned { scene_aabb = 0, scene_obb = 1, scene_sphere = 2, scene_plane = 3, scene_poly = 4, scene_copy = 5 };

template <class T> struct SceneInput {
    Ray<T> ray;
    std::vector<Primitive<T>> prims;
    // The planes of the polyhedra (each ConvexPolyhedron in prims spans one of these).
    std::vector<std::shared_ptr<const std::vector<Plane<T>>>> plane_sets;
    int leaf_size = 4, bins = 16;
    std::span<const Primitive<T>> view() const { return prims; }
};

template <class T> class SceneDecoder : FieldReader {
public:
    SceneDecoder(const std::uint8_t* data, std::size_t size) : FieldReader(data, size) {}

    SceneInput<T> decode() {
        SceneInput<T> in{};
        const unsigned header = p_.ConsumeIntegral<std::uint8_t>();
        const unsigned t_style = (header >> kTRangeShift) & 3u;
        const unsigned opt = p_.ConsumeIntegral<std::uint8_t>();
        in.leaf_size = 1 + int(opt & 7u);
        in.bins = 2 + int(opt >> 3);
        const unsigned n = p_.ConsumeIntegral<std::uint8_t>() % unsigned(kMaxScenePrims + 1);
        // Every number lives in `num_` (reserved once: the field pointers stay valid); a
        // primitive is a kind and a range of numbers there.
        num_.reserve(std::size_t(kMaxScenePrims) * 4 * kMaxScenePlanes + kRayFields);
        struct Rec {
            unsigned kind;
            std::size_t first, count;
        };
        std::vector<Rec> recs;
        for (unsigned i = 0; i < n; ++i) {
            const unsigned k = p_.ConsumeIntegral<std::uint8_t>();
            unsigned kind = k & 7u;
            if (kind >= 6) kind = scene_aabb;
            if (kind == scene_copy) {
                if (recs.empty()) {
                    recs.push_back({scene_aabb, read_fields(6, true), 6});
                } else {
                    recs.push_back(recs[(k >> 3) % recs.size()]);
                }
                continue;
            }
            std::size_t count = 0;
            switch (kind) {
                case scene_aabb: count = 6; break;
                case scene_obb: count = 15; break;
                case scene_sphere:
                case scene_plane: count = 4; break;
                default: count = 4 * (p_.ConsumeIntegral<std::uint8_t>() % unsigned(kMaxScenePlanes + 1)); break;
            }
            recs.push_back({kind, read_fields(count, false), count});
        }
        const std::size_t ray_first = num_.size();
        constexpr T inf = std::numeric_limits<T>::infinity();
        for (int k = 0; k < kRayFields; ++k) {
            if (k == kRayFields - 2 && t_style <= 1) push(t_style == 0 ? T(0) : -inf);
            else if (k == kRayFields - 1 && t_style <= 2) push(inf);
            else push(value(fields_, int(fields_.size())));
            done_ = int(fields_.size());
        }
        for (int i = 0; i < kMaxPatches && p_.remaining_bytes() > 0; ++i) {
            const std::size_t dst = p_.ConsumeIntegral<std::uint16_t>() % fields_.size();
            *fields_[dst] = value(fields_, int(fields_.size()));
        }
        const T* v = num_.data();
        in.ray.origin = Vec3<T>(v[ray_first], v[ray_first + 1], v[ray_first + 2]);
        in.ray.direction = Vec3<T>(v[ray_first + 3], v[ray_first + 4], v[ray_first + 5]);
        in.ray.t_min = v[ray_first + 6];
        in.ray.t_max = v[ray_first + 7];
        for (const Rec& r : recs) {
            const T* x = v + r.first;
            switch (r.kind) {
                case scene_aabb: in.prims.push_back(Aabb<T>{Vec3<T>(x[0], x[1], x[2]), Vec3<T>(x[3], x[4], x[5])}); break;
                case scene_obb: {
                    Obb<T> o;
                    o.center = Vec3<T>(x[0], x[1], x[2]);
                    for (int j = 0; j < 9; ++j) o.axes.data()[j] = x[3 + j];  // column-major
                    o.half_extent = Vec3<T>(x[12], x[13], x[14]);
                    in.prims.push_back(o);
                    break;
                }
                case scene_sphere: in.prims.push_back(Sphere<T>{Vec3<T>(x[0], x[1], x[2]), x[3]}); break;
                case scene_plane: in.prims.push_back(Plane<T>{Vec3<T>(x[0], x[1], x[2]), x[3]}); break;
                default: {
                    auto planes = std::make_shared<std::vector<Plane<T>>>();
                    for (std::size_t q = 0; q < r.count; q += 4)
                        planes->push_back(Plane<T>{Vec3<T>(x[q], x[q + 1], x[q + 2]), x[q + 3]});
                    in.prims.push_back(ConvexPolyhedron<T>{std::span<const Plane<T>>(*planes)});
                    in.plane_sets.push_back(std::move(planes));
                    break;
                }
            }
        }
        return in;
    }

private:
    void push(T x) {
        num_.push_back(x);
        fields_.push_back(&num_.back());
    }
    // `count` fields decoded one by one (zeros when `zeros`); returns the first's index.
    std::size_t read_fields(std::size_t count, bool zeros) {
        const std::size_t first = num_.size();
        for (std::size_t j = 0; j < count; ++j) {
            push(zeros ? T(0) : value(fields_, int(fields_.size())));
            done_ = int(fields_.size());
        }
        return first;
    }

    std::vector<T> num_;
    std::vector<T*> fields_;
};

template <class T> SceneInput<T> decode_scene(const std::uint8_t* data, std::size_t size) {
    return SceneDecoder<T>(data, size).decode();
}

// The bytes of a scene (at most kMaxScenePrims primitives, polyhedra of at most
// kMaxScenePlanes planes: `fits`), every field in its most compact class, no copies, no
// patches; t range [decoded, decoded], or [0, +inf) when it is that range.
template <class T> bool scene_fits(std::span<const Primitive<T>> prims) {
    if (prims.size() > std::size_t(kMaxScenePrims)) return false;
    for (const Primitive<T>& p : prims)
        if (const auto* c = std::get_if<ConvexPolyhedron<T>>(&p); c && c->planes.size() > std::size_t(kMaxScenePlanes))
            return false;
    return true;
}

template <class T>
std::vector<std::uint8_t> encode_scene(const Ray<T>& ray, std::span<const Primitive<T>> prims, int leaf_size = 4, int bins = 16) {
    const bool default_range = to_bits(ray.t_min) == to_bits(T(0)) && ray.t_max == std::numeric_limits<T>::infinity();
    Encoder e;
    e.put(std::uint8_t((std::is_same_v<T, double> ? kDoubleBit : 0u) | ((default_range ? 0u : 3u) << kTRangeShift)));
    e.put(std::uint8_t(unsigned(leaf_size - 1) | unsigned(bins - 2) << 3));
    e.put(std::uint8_t(prims.size()));
    const auto put3 = [&e](const Vec3<T>& v) {
        for (int j = 0; j < 3; ++j) encode_value(e, v[j]);
    };
    for (const Primitive<T>& p : prims) {
        std::visit(
            [&](const auto& s) {
                using S = std::decay_t<decltype(s)>;
                if constexpr (std::is_same_v<S, Aabb<T>>) {
                    e.put(std::uint8_t(scene_aabb));
                    put3(s.lo);
                    put3(s.hi);
                } else if constexpr (std::is_same_v<S, Obb<T>>) {
                    e.put(std::uint8_t(scene_obb));
                    put3(s.center);
                    for (int j = 0; j < 9; ++j) encode_value(e, s.axes.data()[j]);
                    put3(s.half_extent);
                } else if constexpr (std::is_same_v<S, Sphere<T>>) {
                    e.put(std::uint8_t(scene_sphere));
                    put3(s.center);
                    encode_value(e, s.radius);
                } else if constexpr (std::is_same_v<S, Plane<T>>) {
                    e.put(std::uint8_t(scene_plane));
                    put3(s.normal);
                    encode_value(e, s.offset);
                } else {
                    e.put(std::uint8_t(scene_poly));
                    e.put(std::uint8_t(s.planes.size()));
                    for (const Plane<T>& q : s.planes) {
                        put3(q.normal);
                        encode_value(e, q.offset);
                    }
                }
            },
            p);
    }
    put3(ray.origin);
    put3(ray.direction);
    if (!default_range) {
        encode_value(e, ray.t_min);
        encode_value(e, ray.t_max);
    }
    return e.bytes();
}

}  // namespace rayproof::fuzz
