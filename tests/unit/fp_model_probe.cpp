// fp_model_probe: a translation unit that uses the kernel, compiled by the test
// fp_model_refused under each floating-point option the kernel refuses
// (rayproof/detail/fp_model.hpp). It must compile with the default model and fail
// with the kernel's #error under each unsafe one.
#include <rayproof/rayproof.hpp>

int main() {
    const rayproof::Ray<double> ray{{0, 0, -5}, {0, 0, 1}};
    const rayproof::Aabb<double> box{{-1, -1, -1}, {1, 1, 1}};
    return rayproof::intersect(ray, box, rayproof::certified) ? 0 : 1;
}
