// ray_aabb_packet_fuzz.cpp — fuzz target: one ray against a packet of boxes
// (ray_aabb_packet.hpp), float and double, W = 4 and 8, all three modes, every lane
// judged by the exact oracle and against the scalar query.
//
// Input: the Aabb targets' format (fuzz_decode.hpp: the header picks float or double;
// ray_aabb_fuzz's corpus is a valid seed corpus here). The decoded box fills the packet's
// lanes in hard variants chosen by a hash of the input bytes: the box itself, one bound
// moved by 1 to 3 ulps either way, the box flat on one axis, grown or shrunk by one ulp
// on every side, and empty slots (lo > hi, a NaN or infinite bound). Both widths are run.
// Checks, per lane i (exact = the oracle on the lane's box):
//   every mode     verdict() == intersect().mask; a lane the oracle calls invalid (an
//                  empty slot, or any lane of an invalid ray) has bit 0 and the fields
//                  of a miss (0, 0, -1)
//   certified      the lane meets the contract (exact verdict and face, faithful t) and
//                  equals the scalar certified query bit for bit; the portable and the
//                  native backends give identical packets
//   conservative   never a false miss; a hit's interval encloses the exact one
//   fast           only the line above
// A violation prints the case in hexadecimal floating point, the lane, the answers and
// the oracle's, then aborts.
#include "fuzz_check.hpp"

#include <rayproof/ray_aabb_packet.hpp>

namespace rayproof::fuzz {
namespace {

std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

template <class T> T ulps(T x, int k) {
    for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<T>::infinity());
    for (; k < 0; ++k) x = std::nextafter(x, -std::numeric_limits<T>::infinity());
    return x;
}

template <class T, int W> AabbPacket<T, W> packet_of(const Aabb<T>& b, std::uint64_t h) {
    AabbPacket<T, W> p;
    const auto next = [&h] { return h = mix(h); };
    for (int k = 0; k < W; ++k) {
        Aabb<T> x = b;
        const int a = int(next() % 3);
        const int n = int(next() % 7) - 3;
        switch (k == 0 ? 0 : next() % 8) {
            case 0:
            case 1: break;
            case 2: x.lo[a] = ulps(x.lo[a], n); break;
            case 3: x.hi[a] = ulps(x.hi[a], n); break;
            case 4: x.lo[a] = x.hi[a] = (n & 1) ? b.lo[a] : b.hi[a]; break;
            case 5:
                for (int i = 0; i < 3; ++i) x.lo[i] = ulps(x.lo[i], -1), x.hi[i] = ulps(x.hi[i], 1);
                break;
            case 6:
                for (int i = 0; i < 3; ++i) x.lo[i] = ulps(x.lo[i], 1), x.hi[i] = ulps(x.hi[i], -1);
                break;
            default:
                if (n < 0) std::swap(x.lo[a], x.hi[a]);
                else if (n == 0) x.lo[a] = std::numeric_limits<T>::quiet_NaN();
                else x.hi[a] = n == 1 ? std::numeric_limits<T>::infinity() : ulps(x.lo[a], -1);
                break;
        }
        p.set(k, x);
    }
    return p;
}

template <class T, int W>
[[noreturn]] void packet_violation(const char* what, const char* mode, const Ray<T>& ray, const AabbPacket<T, W>& p,
                                   int i, const Hit<T>& got, const std::string& other) {
    const std::string d = std::string(what) + " (packet W=" + std::to_string(W) + ", mode " + mode + ", " +
                          (std::is_same_v<T, float> ? "float" : "double") + ")";
    filter(d);
    std::cerr << "\n==== rayproof fuzz: contract violation: " << d << '\n';
    if (!current_input().empty()) std::cerr << "input:    " << current_input() << '\n';
    std::cerr << "ray:      " << ray << "\nlane:     " << i << "\nbox:      " << p.box(i) << "\nanswer:   " << got
              << "\n" << other << '\n';
    std::cerr.flush();
    std::abort();
}

template <class T, int W, class Mode> void check_packet_mode(const Ray<T>& ray, const AabbPacket<T, W>& p, Mode mode) {
    const PreparedRay<T> pr(ray);
    const PacketHit<T, W> h = intersect(pr, p, mode);
    const std::uint32_t v = verdict(pr, p, mode);
    if (v != h.mask)
        packet_violation("verdict() differs from intersect().mask", mode_name(mode), ray, p, -1, Hit<T>{},
                         "verdict:  " + std::to_string(v) + ", mask " + std::to_string(h.mask));
    for (int i = 0; i < W; ++i) {
        const Aabb<T> box = p.box(i);
        const oracle::Exact<T> ex = oracle::exact(ray, box);
        const Hit<T> x = h.lane(i);
        std::ostringstream os;
        os << "exact:    " << ex;
        if (ex.verdict == Verdict::invalid) {
            if (x.verdict != Verdict::miss || x.t_enter != 0 || x.t_exit != 0 || x.face != -1)
                packet_violation("empty slot or invalid ray not answered as an empty lane", mode_name(mode), ray, p, i,
                                 x, os.str());
            continue;
        }
        const oracle::ContractCheck c = oracle::check_contract(ray, box, x, ex, mode);
        if (!c.ok()) {
            os << "\njudge:    " << c.mode_judgement();
            packet_violation(oracle::describe(c.first()), mode_name(mode), ray, p, i, x, os.str());
        }
        if constexpr (std::is_same_v<Mode, certified_t>) {
            const Hit<T> s = intersect(ray, box, certified);
            const bool same = x.verdict == s.verdict && same_bits(x.t_enter, s.t_enter) &&
                              same_bits(x.t_exit, s.t_exit) && x.face == s.face;
            if (!same) {
                os << "\nscalar:   " << s;
                packet_violation("certified lane differs from the scalar query", "certified", ray, p, i, x, os.str());
            }
        }
    }
    if constexpr (std::is_same_v<Mode, certified_t>) {
        const PacketHit<T, W> a = detail::packet_intersect<detail::simd::portable>(pr, p, certified);
        for (int i = 0; i < W; ++i)
            if (!same_answer(a.lane(i), h.lane(i)) || ((a.mask ^ h.mask) >> i & 1))
                packet_violation("portable backend differs from native", "certified", ray, p, i, a.lane(i),
                                 "native:   " + std::string(detail::simd::native_name()));
    }
}

template <class T, int W> void check_packet(const Ray<T>& ray, const Aabb<T>& box, std::uint64_t h) {
    const AabbPacket<T, W> p = packet_of<T, W>(box, h);
    check_packet_mode(ray, p, certified);
    check_packet_mode(ray, p, conservative);
    check_packet_mode(ray, p, fast);
}

template <class T> void check_input(const std::uint8_t* data, std::size_t size) {
    const auto in = decode<T, Aabb<T>>(data, size);
    std::uint64_t h = size;
    for (std::size_t i = 0; i < size; ++i) h = mix(h ^ data[i]);
    if (print_cases()) std::cerr << "packet case: " << in.ray << ' ' << in.shape << std::endl;
    check_packet<T, 4>(in.ray, in.shape, h);
    check_packet<T, 8>(in.ray, in.shape, mix(h));
}

}  // namespace
}  // namespace rayproof::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace rayproof::fuzz;
    try {
        if (is_double(data, size)) check_input<double>(data, size);
        else check_input<float>(data, size);
    } catch (const Filtered&) {
    }
    return 0;
}
