// Guard against the g++ 12.2 SLP miscompilation (docs/compiler-bugs.md), built with the
// kernel's interface flags (which no longer switch the vectorizer off): the reproducer's
// loops, once with a plain cast and once through the kernel's detail::narrow. Every
// value stored through narrow must be a float, bit for bit the one a volatile float
// (which no optimizer can elide) gives; a compiler or flag set that drops that rounding
// fails this test. Whether the plain cast kept its rounding is printed: it shows that
// the pattern still triggers the bug where the compiler has it.
#include <rayproof/detail/rounding.hpp>

#include <cstdio>
#include <cstring>
#include <random>

namespace {

std::mt19937_64 rng(1);
double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
float plain(double x) { return (float)x; }
float guarded(double x) { return rayproof::detail::narrow<float>(x); }
float reference(double x) {
    volatile float f = (float)x;
    return f;
}

struct C {
    double half[3];
};

// The reproducer's two loops, with the conversion f.
template <float (*f)(double)> C fill() {
    rng.seed(1);
    C c;
    for (int i = 0; i < 3; i++) c.half[i] = f(uni(0.1, 5));
    double n2 = 9;
    for (int i = 0; i < 3; i++) c.half[i] = f(c.half[i] * n2);
    return c;
}

// How many values of c differ from the reference's, printed.
int report(const C& c, const C& want, const char* name) {
    int bad = 0;
    for (int i = 0; i < 3; i++) {
        const bool same = std::memcmp(&c.half[i], &want.half[i], sizeof(double)) == 0;
        std::printf("%s: %a %s\n", name, c.half[i], same ? "rounded" : "NOT ROUNDED");
        bad += !same;
    }
    return bad;
}

}  // namespace

int main() {
    const C want = fill<reference>();
    report(fill<plain>(), want, "plain cast");
    return report(fill<guarded>(), want, "detail::narrow");
}
