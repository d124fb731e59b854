// rayproof/rayproof.hpp — the front door: the whole kernel.
//
//   #include <rayproof/rayproof.hpp>
//   rayproof::Ray<double> ray{{0, 0, -5}, {0, 0, 1}};
//   rayproof::Aabb<double> box{{-1, -1, -1}, {1, 1, 1}};
//   auto hit = rayproof::intersect(ray, box, rayproof::certified);
//   if (hit) use(hit.t_enter, hit.face, rayproof::normal(box, hit, ray));
//   auto sp = rayproof::surface_point(ray, box, hit);     // the point, its error bound
//   auto origin = rayproof::spawn_origin(sp, +1);         // a secondary ray's origin
//
// Meaning of every answer: docs/semantics.md. One header per query pair below; the
// internals live in detail/. Every header here stands alone (any order compiles).
#pragma once

#include <rayproof/bvh.hpp>
#include <rayproof/closest.hpp>
#include <rayproof/fp_env_scope.hpp>
#include <rayproof/intersect.hpp>
#include <rayproof/io.hpp>
#include <rayproof/normal.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_aabb.hpp>
#include <rayproof/ray_aabb_packet.hpp>
#include <rayproof/ray_obb.hpp>
#include <rayproof/ray_plane.hpp>
#include <rayproof/ray_polyhedron.hpp>
#include <rayproof/ray_sphere.hpp>
#include <rayproof/surface_point.hpp>
#include <rayproof/types.hpp>
#include <rayproof/version.hpp>
