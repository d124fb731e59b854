// bench/ray_plane_bench.cpp — ray against Plane: the kernel's three modes and the plain
// baselines on every workload (scalar), and the batch sweep (see bench_common.hpp).
#include "bench_common.hpp"

namespace rayproof::bench {
void register_plane() { register_shape<Plane>(); }
}  // namespace rayproof::bench
