// rayproof showcase — a few rays chosen to show the kernel's exact meaning at the
// cases that break textbook code (parallel rays on a slab plane with +0 and -0,
// corners, tangents, rays lying in a plane, clipping by t_min/t_max, invalid input),
// each answered in every mode this build has.
#include <rayproof/rayproof.hpp>

#include <cstdio>
#include <limits>
#include <string>

namespace {

using namespace rayproof;
using R = Ray<double>;
using V = Vec3<double>;

template <class Shape> struct Showcase {
    const char* what;
    R ray;
    Shape shape;
};

std::string describe(const Hit<double>& h) {
    char buf[160];
    if (h.verdict != Verdict::hit) return to_string(h.verdict);
    std::snprintf(buf, sizeof buf, "hit [%.17g, %.17g] face %d", double(h.t_enter), double(h.t_exit), h.face);
    return buf;
}

template <class Shape, class Mode> std::string answer(const Showcase<Shape>& c, Mode m) {
    if constexpr (Answerable<double, Shape, Mode>)
        return describe(intersect(c.ray, c.shape, m));
    else
        return "(mode not in this build)";
}

template <class Shape> void table(const char* shape_name, std::initializer_list<Showcase<Shape>> cases) {
    std::printf("\n%s\n", shape_name);
    for (const auto& c : cases) {
        std::printf("  %s\n", c.what);
        std::printf("    %-13s %s\n", "fast", answer(c, fast).c_str());
        std::printf("    %-13s %s\n", "conservative", answer(c, conservative).c_str());
        std::printf("    %-13s %s\n", "certified", answer(c, certified).c_str());
    }
}

}  // namespace

int rayproof_showcase() {
    const double inf = std::numeric_limits<double>::infinity();
    const Aabb<double> cube{V(-1, -1, -1), V(1, 1, 1)};
    std::printf("rayproof showcase: double precision; the cube is [-1,1]^3\n");
    table<Aabb<double>>("Ray vs Aabb (closed box)", {
        {"along +x from (-5,0,0)", R{V(-5, 0, 0), V(1, 0, 0)}, cube},
        {"parallel to y=1, origin on that plane, d=(1,+0,+0)", R{V(-5, 1, 0), V(1, 0, 0)}, cube},
        {"parallel to y=1, origin on that plane, d=(1,-0,-0)", R{V(-5, 1, 0), V(1, -0.0, -0.0)}, cube},
        {"parallel, origin just outside y=1 (next double up)", R{V(-5, std::nextafter(1.0, 2.0), 0), V(1, 0, 0)}, cube},
        {"through the corner (-1,-1,-1) towards (1,1,1)", R{V(-3, -3, -3), V(1, 1, 1)}, cube},
        {"grazing the edge y=1,z=1", R{V(-3, 1, 1), V(1, 0, 0)}, cube},
        {"from the centre (inside: face -1)", R{V(0, 0, 0), V(0, 0, 1)}, cube},
        {"t_max = 3.5 stops before the box", R{V(-5, 0, 0), V(1, 0, 0), 0, 3.5}, cube},
        {"invalid: lo > hi", R{V(-5, 0, 0), V(1, 0, 0)}, Aabb<double>{V(1, -1, -1), V(-1, 1, 1)}},
    });
    Mat3<double> rot;
    rot << 3, -4, 0, 4, 3, 0, 0, 0, 5;  // integer, orthogonal, not normalized (|a_i| = 5)
    const Obb<double> obb{V(0, 0, 0), rot, V(25, 25, 25)};
    table<Obb<double>>("Ray vs Obb (axes (3,4,0),(-4,3,0),(0,0,5) as stored, half extents 25: half-widths 5)", {
        {"along +x from (-10,0,0)", R{V(-10, 0, 0), V(1, 0, 0)}, obb},
        {"through the corner (1,-7,0) = -5(a0+a1)/|a|, along the diagonal", R{V(6, -42, 0), V(-5, 35, 0)}, obb},
        {"invalid: dependent axes", R{V(-5, 0, 0), V(1, 0, 0)},
         Obb<double>{V(0, 0, 0), (Mat3<double>() << 1, 2, 3, 4, 5, 9, 7, 8, 15).finished(), V(1, 1, 1)}},
    });
    const Plane<double> floor{V(0, 1, 0), -1};
    table<Plane<double>>("Ray vs Plane (surface y = -1)", {
        {"down from (0,3,0)", R{V(0, 3, 0), V(0, -1, 0)}, floor},
        {"lying in the plane (whole range)", R{V(0, -1, 0), V(1, 0, 1), -2, inf}, floor},
        {"parallel above the plane", R{V(0, 0, 0), V(1, 0, 0)}, floor},
        {"nearly parallel: d=(1,-1e-300,0)", R{V(0, 0, 0), V(1, -1e-300, 0)}, floor},
        {"invalid: zero normal", R{V(0, 3, 0), V(0, -1, 0)}, Plane<double>{V(0, 0, 0), 1}},
    });
    const Sphere<double> ball{V(0, 0, 0), 5};
    table<Sphere<double>>("Ray vs Sphere (closed ball, radius 5 at the origin)", {
        {"through the centre from (-10,0,0)", R{V(-10, 0, 0), V(1, 0, 0)}, ball},
        {"tangent at (0,5,0)", R{V(-10, 5, 0), V(1, 0, 0)}, ball},
        {"tangent, 3-4-5 triangle: from (-3,4,0)+(4,3,0)s", R{V(-7, 1, 0), V(4, 3, 0)}, ball},
        {"far small sphere: radius 1e-3 at 1e6, tangent", R{V(0, 1e-3, 0), V(1, 0, 0)},
         Sphere<double>{V(1e6, 0, 0), 1e-3}},
        {"invalid: negative radius", R{V(-10, 0, 0), V(1, 0, 0)}, Sphere<double>{V(0, 0, 0), -1}},
    });
    return 0;
}
