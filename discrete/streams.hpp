#pragma once
// Reproducible random streams (STYLE: one stream per site from (seed, site)): results do not depend
// on iteration order or thread count. Engines are Boost.Random Mersenne twisters seeded through
// boost::random::seed_seq, and their state can be saved and restored as text (checkpoints).
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/seed_seq.hpp>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace slipfront::discrete {

using Engine = boost::random::mt19937_64;

/// The engine of `site` for a run seeded with `seed` (a fixed mapping: part of the output contract).
inline Engine site_engine(std::uint64_t seed, std::uint64_t site) {
  boost::random::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                              static_cast<std::uint32_t>(site), static_cast<std::uint32_t>(site >> 32),
                              0x51695f5u /* slipfront */};
  return Engine(seq);
}

inline std::vector<Engine> site_engines(std::uint64_t seed, std::size_t sites) {
  std::vector<Engine> e;
  e.reserve(sites);
  for (std::size_t i = 0; i < sites; ++i) e.push_back(site_engine(seed, i));
  return e;
}

inline std::string save_state(const Engine& e) {
  std::ostringstream os;
  os << e;
  return os.str();
}
inline void load_state(Engine& e, const std::string& s) {
  std::istringstream is(s);
  is >> e;
}

/// An engine in a checkpoint (core::Archive): its state as text.
template <class Ar>
void serialize_engine(Ar& ar, Engine& e) {
  std::string s = ar.loading() ? std::string() : save_state(e);
  ar(s);
  if (ar.loading()) load_state(e, s);
}

/// Uniform number in the open interval (0, 1) from 53 random bits.
inline double uniform01(Engine& e) {
  return (static_cast<double>(e() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

}  // namespace slipfront::discrete
