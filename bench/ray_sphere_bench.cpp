// bench/ray_sphere_bench.cpp — ray against Sphere: the kernel's three modes and the plain
// baselines on every workload (scalar), and the batch sweep (see bench_common.hpp).
#include "bench_common.hpp"

namespace rayproof::bench {
void register_sphere() { register_shape<Sphere>(); }
}  // namespace rayproof::bench
