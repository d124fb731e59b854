// Guard against the g++ 12.2 SLP miscompilation (docs/compiler-bugs.md): built with the
// flags that rayproof::kernel gives its users, every value stored must be a float. A
// compiler or flag set that drops the rounding fails this test.
#include <cstdio>
#include <random>
std::mt19937_64 rng(1);
double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
float f32(double x) { return (float)x; }
struct C { double half[3]; };
int main() {
  int bad = 0;
  C c;
  for (int i = 0; i < 3; i++) c.half[i] = f32(uni(0.1, 5));
  double n2 = 9;
  for (int i = 0; i < 3; i++) c.half[i] = f32(c.half[i] * n2);
  for (int i = 0; i < 3; i++) { const bool ok = (double)(float)c.half[i] == c.half[i]; printf("%a %d\n", c.half[i], ok); bad += !ok; }
  return bad;
}
