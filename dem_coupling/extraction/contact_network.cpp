#include "dem_coupling/extraction/contact_network.hpp"

#include <cmath>

namespace granflow::dem {

NetworkState network_state(long particles, const std::vector<ContactPair>& contacts) {
  NetworkState s;
  if (particles <= 0) return s;
  s.contacts = double(contacts.size());
  s.coordination = 2.0 * s.contacts / double(particles);
  // Peel the particles with < 2 live contacts until none is left (the 2-core of the graph).
  const auto n = static_cast<std::size_t>(particles);
  std::vector<int> degree(n, 0);
  std::vector<std::vector<long>> touching(n);
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    ++degree[contacts[k].i];
    ++degree[contacts[k].j];
    touching[contacts[k].i].push_back(long(k));
    touching[contacts[k].j].push_back(long(k));
  }
  std::vector<char> removed(n, 0), dead(contacts.size(), 0);
  std::vector<long> queue;
  for (long p = 0; p < particles; ++p)
    if (degree[p] < 2) queue.push_back(p);
  while (!queue.empty()) {
    const long p = queue.back();
    queue.pop_back();
    if (removed[p]) continue;
    removed[p] = 1;
    for (long k : touching[p]) {
      if (dead[k]) continue;
      dead[k] = 1;
      const long other = contacts[k].i == p ? contacts[k].j : contacts[k].i;
      if (--degree[other] < 2 && !removed[other]) queue.push_back(other);
    }
  }
  double kept = 0.0, live = 0.0;
  for (long p = 0; p < particles; ++p) kept += removed[p] ? 0.0 : 1.0;
  std::array<double, 6> f{};
  const int pair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (dead[k]) continue;
    live += 1.0;
    for (int a = 0; a < 6; ++a) f[a] += contacts[k].n[pair[a][0]] * contacts[k].n[pair[a][1]];
  }
  s.nonrattler_fraction = kept / double(particles);
  if (kept > 0.0) s.coordination_nonrattler = 2.0 * live / kept;
  if (live > 0.0) {
    for (int a = 0; a < 6; ++a) s.fabric[a] = f[a] / live - (a < 3 ? 1.0 / 3.0 : 0.0);
    double norm2 = 0.0;  // F':F' (off-diagonal entries twice)
    for (int a = 0; a < 6; ++a) norm2 += (a < 3 ? 1.0 : 2.0) * s.fabric[a] * s.fabric[a];
    s.anisotropy = std::sqrt(1.5 * norm2);
  }
  return s;
}

}  // namespace granflow::dem
