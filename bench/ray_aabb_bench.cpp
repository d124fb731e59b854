// bench/ray_aabb_bench.cpp — ray against Aabb: the kernel's three modes and the plain
// baselines on every workload (scalar), and the batch sweep (see bench_common.hpp).
#include "bench_common.hpp"

namespace rayproof::bench {
void register_aabb() { register_shape<Aabb>(); }
}  // namespace rayproof::bench
