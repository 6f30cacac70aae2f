// Deterministic random numbers. Every draw in calibench derives from (config seed, trial index)
// through TrialSeed(), and from a named stream inside a trial, so results never depend on the
// thread count or on the order in which trials run.
//
// Generator: xoshiro256** seeded by SplitMix64 (both public-domain algorithms by Vigna), with our
// own uniform and Gaussian transforms (Box-Muller) so the numbers are the same with any standard
// library. And with any compiler: the arguments of one call are evaluated in an order the
// compiler picks (g++ last first, clang++ first first), so two draws are never arguments of one
// call (a constructor's included). They are drawn in sequence, in g++'s order (the last
// coordinate first), the order every published number was drawn in: NormalPair below.
#pragma once

#include <cstdint>

namespace calibench {

// Mixes a 64-bit value (SplitMix64 finaliser): consecutive inputs give unrelated outputs.
uint64_t Mix64(uint64_t x);

// The seed of trial `trial` of a scenario whose config says `config_seed`.
inline uint64_t TrialSeed(uint64_t config_seed, uint64_t trial) {
  return Mix64(Mix64(config_seed) ^ (trial + 0x632be59bd9b4e019ULL));
}

// Independent streams inside one trial (noise on points, noise on pixels, ...).
enum class RngStream : uint64_t {
  kPointNoise = 1,
  kPixelNoise = 2,
  kScene = 3,
  kMotionPhase = 4,
  kOutliers = 5,
};

class Rng {
 public:
  explicit Rng(uint64_t seed);
  Rng(uint64_t trial_seed, RngStream stream)
      : Rng(Mix64(trial_seed ^ (static_cast<uint64_t>(stream) * 0x9e3779b97f4a7c15ULL))) {}

  uint64_t NextU64();
  // Uniform in [0, 1) with 53 random bits.
  double Uniform();
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double Normal();

 private:
  uint64_t s_[4];
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// A 2-vector (any type constructible from two doubles) of standard normals, y drawn first.
template <typename Vector2>
Vector2 NormalPair(Rng* rng) {
  const double y = rng->Normal();
  return Vector2(rng->Normal(), y);
}

}  // namespace calibench
