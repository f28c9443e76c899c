// Standard normal draws: xoshiro256++ bits, the ziggurat of 128 layers (see normal_draws.hpp).
//
// Ziggurat (Marsaglia and Tsang, "The Ziggurat Method for Generating Random Variables", 2000):
// the area under f(x) = exp(-x^2 / 2), x >= 0, is covered by 128 stacked layers of equal area
// v: 127 rectangles and a base made of a rectangle and the tail beyond r. A draw picks a layer
// and a point x inside its width; most points lie under the next layer up, inside f, and are
// taken at once; the others are tested against f (the wedge) or drawn from the tail.
// Here each draw uses 32 bits: 7 for the layer, 1 for the sign, 24 for the point (float32's
// resolution), so the layer and the point come from separate bits.
#include "grasp_core/normal_draws.hpp"

#include <array>
#include <cmath>
#include <cstring>

namespace grasp_core {

namespace {

constexpr int kLayers = 128;
constexpr double kTail = 3.442619855899;            ///< r: where the tail starts
constexpr double kLayerArea = 9.91256303526217e-3;  ///< v: the area of each layer
constexpr double kPointScale = 16777216.0;          ///< 2^24: points are 24-bit integers

double density(double x) { return std::exp(-0.5 * x * x); }

/// The layer tables: a point u (24 bits) of layer i is x = u * width[i]; u < accept[i] lies
/// under the layer above (taken at once); edge[i] = f at the layer's right edge.
struct Tables {
  std::array<std::uint32_t, kLayers> accept{};
  std::array<float, kLayers> width_f{};
  std::array<double, kLayers> width{};
  std::array<double, kLayers> edge{};

  Tables() {
    double x = kTail;
    const double base = kLayerArea / density(x);  // the base rectangle's width (its area is v)
    accept[0] = static_cast<std::uint32_t>(x / base * kPointScale);
    accept[1] = 0;
    width[0] = base / kPointScale;
    width[kLayers - 1] = x / kPointScale;
    edge[0] = 1.0;
    edge[kLayers - 1] = density(x);
    for (int i = kLayers - 2; i >= 1; --i) {
      const double above = std::sqrt(-2.0 * std::log(kLayerArea / x + density(x)));
      accept[static_cast<std::size_t>(i + 1)] = static_cast<std::uint32_t>(above / x * kPointScale);
      x = above;
      edge[static_cast<std::size_t>(i)] = density(x);
      width[static_cast<std::size_t>(i)] = x / kPointScale;
    }
    for (int i = 0; i < kLayers; ++i)
      width_f[static_cast<std::size_t>(i)] = static_cast<float>(width[static_cast<std::size_t>(i)]);
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

/// xoshiro256++ with its state expanded from one seed by splitmix64.
class Bits {
 public:
  explicit Bits(std::uint64_t seed) {
    for (std::uint64_t& w : s_) {
      seed += 0x9e3779b97f4a7c15ULL;
      std::uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      w = z ^ (z >> 31);
    }
  }

  std::uint64_t next() {
    const std::uint64_t out = rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return out;
  }

  /// Uniform in (0, 1) from 53 bits.
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }

 private:
  std::uint64_t s_[4];
};

/// A draw whose 32 bits `chunk` fell outside the layer's inner part: the wedge test, or the
/// tail for the base layer; new chunks until one is accepted.
float slow_draw(std::uint32_t chunk, Bits& bits) {
  const Tables& t = tables();
  for (;;) {
    const std::size_t layer = chunk & (kLayers - 1);
    const bool negative = (chunk & 128u) != 0;
    const std::uint32_t u = chunk >> 8;
    if (u < t.accept[layer]) {
      const float inner = static_cast<float>(u) * t.width_f[layer];
      return negative ? -inner : inner;
    }
    double x = static_cast<double>(u) * t.width[layer];
    if (layer == 0) {  // the tail beyond r
      double y;
      do {
        x = -std::log(bits.uniform()) / kTail;
        y = -std::log(bits.uniform());
      } while (y + y < x * x);
      x += kTail;
      return static_cast<float>(negative ? -x : x);
    }
    const double f0 = t.edge[layer], f1 = t.edge[layer - 1];
    if (f0 + bits.uniform() * (f1 - f0) < density(x)) return static_cast<float>(negative ? -x : x);
    chunk = static_cast<std::uint32_t>(bits.next());
  }
}

inline float draw(std::uint32_t chunk, Bits& bits, const Tables& t) {
  const std::size_t layer = chunk & (kLayers - 1);
  const std::uint32_t u = chunk >> 8;
  if (u < t.accept[layer]) {
    // the sign bit (bit 7 of the chunk) into the float's sign: no branch
    const float x = static_cast<float>(u) * t.width_f[layer];
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    b ^= (chunk & 128u) << 24;
    float y;
    std::memcpy(&y, &b, sizeof y);
    return y;
  }
  return slow_draw(chunk, bits);
}

}  // namespace

void fill_standard_normal(std::uint64_t seed, std::size_t n, float* out) {
  const Tables& t = tables();
  Bits bits(seed);
  std::size_t p = 0;
  for (; p + 1 < n; p += 2) {
    const std::uint64_t w = bits.next();
    out[p] = draw(static_cast<std::uint32_t>(w), bits, t);
    out[p + 1] = draw(static_cast<std::uint32_t>(w >> 32), bits, t);
  }
  if (p < n) out[p] = draw(static_cast<std::uint32_t>(bits.next()), bits, t);
}

}  // namespace grasp_core
