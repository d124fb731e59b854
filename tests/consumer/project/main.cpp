// A program outside the project, built against the installed kernel.
#include <rayproof/rayproof.hpp>

#include <cstdio>

int main() {
    const rayproof::Ray<double> ray{{-4, 0, 0}, {1, 0, 0}};
    const rayproof::Aabb<double> box{{-1, -1, -1}, {1, 1, 1}};
    const auto hit = rayproof::intersect(ray, box, rayproof::fast);
    std::printf("%s [%g, %g] face %d\n", rayproof::to_string(hit.verdict), hit.t_enter, hit.t_exit, hit.face);
    return hit ? 0 : 1;
}
