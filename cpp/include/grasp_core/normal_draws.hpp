// Standard normal draws for the simulated sensor's noise: a seeded stream, fast enough to draw
// one per pixel of every frame (about 1 ns a draw where numpy's generator takes 8).
//
// Uniform bits: xoshiro256++ (Blackman and Vigna), its state expanded from one 64-bit seed by
// splitmix64. Normals: Marsaglia and Tsang's ziggurat of 128 layers (each 64-bit output gives
// two draws: a signed 32-bit value picks the layer and the point in it); the tables are
// computed once from the layer construction, in double precision. The same seed gives the
// same draws on every run.
#pragma once

#include <cstddef>
#include <cstdint>

namespace grasp_core {

/// Fills out[0..n) with standard normal draws (float32) of the stream of `seed`.
void fill_standard_normal(std::uint64_t seed, std::size_t n, float* out);

}  // namespace grasp_core
