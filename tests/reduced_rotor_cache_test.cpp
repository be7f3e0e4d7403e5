// The fit's cache of reduced rotors (tools/fit/reduced_rotor_cache.hpp): a model built on a
// cached rotor runs bit for bit as one built from scratch, one rotor is reduced once, and a
// config that moves a station (an unbalance plane) gets its own reduction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

#include "rt_core/simulator.hpp"
#include "test_configs.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"

namespace ambdrop::reduced_rotor_cache_test {
namespace {

ModelParams LoadTestConfigForCache() {
  return testing::LoadTestConfig("chen_itri_flexible.toml");
}

// The state after a drop onto the TDBs: what differs in a reduction shows here. `peak_N`: the
// largest contact force on the way, so a caller can see that the run covered contact.
StateVector DropState(const Model& model, int steps, double* peak_N = nullptr) {
  Simulator sim(model);
  State s = sim.InitialState();
  Observation o;
  double peak = 0.0;
  for (int i = 0; i < steps; ++i) {
    if (sim.Step(&s, ControlInput::PowerOff()) != StepStatus::kOk) break;
    sim.Observe(s, &o);
    for (std::size_t t = 0; t < model.params.tdbs.size(); ++t) {
      peak = std::max(peak, o.tdb[t].normal_force_N);
    }
  }
  if (peak_N != nullptr) *peak_N = peak;
  return s.y;
}

TEST(ReducedRotorCache, ModelOnACachedRotorRunsBitForBitAsOneBuiltAfresh) {
  const ModelParams p = LoadTestConfigForCache();
  ReducedRotorCache cache;
  const Model fresh = BuildModel(p);
  const Model first = cache.BuildModel(p);
  const Model again = cache.BuildModel(p);  // from the cache
  double peak_N = 0.0;
  const StateVector a = DropState(fresh, 8000, &peak_N);
  for (const Model* m : {&first, &again}) {
    const StateVector b = DropState(*m, 8000);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())),
              0);
  }
  // The rotor has fallen onto its TDBs, so the comparison covers contact: more than the
  // 16 kg per TDB could press statically.
  EXPECT_GT(peak_N, 32.0 * 9.81);
}

TEST(ReducedRotorCache, ReducesEachRotorOnceAndAMovedStationAfresh) {
  const ModelParams p = LoadTestConfigForCache();
  ReducedRotorCache cache;
  const auto r1 = cache.Get(p);
  ModelParams misaligned = p;  // an effect that leaves the rotor alone
  misaligned.tdbs.front().misalignment = {true, 2e-5, -3e-5};
  EXPECT_EQ(cache.Get(misaligned).get(), r1.get());

  ModelParams unbalanced = p;  // a new station: the mesh gets a node there
  UnbalanceParams u;
  u.position_m = 0.37 * (p.tdbs.front().position_m + p.tdbs.back().position_m);
  u.mass_kg = 1.0;
  u.eccentricity_m = 1e-4;
  unbalanced.unbalances.push_back(u);
  const auto r2 = cache.Get(unbalanced);
  EXPECT_NE(r2.get(), r1.get());
  const ReducedRotor expected = BuildReducedRotor(unbalanced);
  EXPECT_EQ(r2->node_positions_m, expected.node_positions_m);
  EXPECT_TRUE(r2->stiffness == expected.stiffness);
  EXPECT_EQ(cache.Get(unbalanced).get(), r2.get());
}

TEST(ReducedRotorCache, ThreadsShareOneRotor) {
  const ModelParams p = LoadTestConfigForCache();
  ReducedRotorCache cache;
  std::vector<std::shared_ptr<const ReducedRotor>> got(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i) {
    threads.emplace_back([&, i] { got[i] = cache.Get(p); });
  }
  for (std::thread& t : threads) t.join();
  // Threads that raced may have built their own copy, but all equal, and later calls share.
  for (const auto& r : got) EXPECT_TRUE(r->basis == got.front()->basis);
  EXPECT_EQ(cache.Get(p).get(), cache.Get(p).get());
}

}  // namespace
}  // namespace ambdrop::reduced_rotor_cache_test
