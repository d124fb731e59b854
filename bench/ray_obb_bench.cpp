// bench/ray_obb_bench.cpp — ray against Obb: the kernel's three modes and the plain
// baselines on every workload (scalar), and the batch sweep (see bench_common.hpp).
#include "bench_common.hpp"

namespace rayproof::bench {
void register_obb() { register_shape<Obb>(); }
}  // namespace rayproof::bench
