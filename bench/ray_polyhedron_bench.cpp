// bench/ray_polyhedron_bench.cpp — ray against ConvexPolyhedron: the kernel's three modes,
// the verdict query and Haines' textbook loop over the planes on the uniform, grazing,
// parallel and extreme workloads (scalar; see bench_common.hpp and workloads.hpp: the
// cases own their planes, no far_small, no batch sweep).
#include "bench_common.hpp"

namespace rayproof::bench {
void register_polyhedron() { register_shape<gen::OwnedPolyhedron>(); }
}  // namespace rayproof::bench
