// The search core's reopening policy (plan/search_core.hpp, ReopenClosed), which IA* with the
// paper's heuristic runs on: with an admissible but inconsistent heuristic, A* with reopening
// returns optimal costs (checked against Dijkstra on random graphs), without reopening it need
// not; with a consistent heuristic both policies expand the same states in the same order.
#include <gtest/gtest.h>

#include <cstdint>
#include <queue>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/plan/search_core.hpp"

namespace {

using namespace starnav;

struct Edge {
  std::uint32_t to;
  double cost;
};

struct ListGraph {
  using cost_type = double;
  std::vector<std::vector<Edge>> out;
  std::size_t state_count() const { return out.size(); }
  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit&& visit) const {
    for (const Edge& e : out[u]) visit(e.to, e.cost);
  }
};

struct TableHeuristic {
  std::vector<double> h;
  double operator()(std::uint32_t id) const { return h[id]; }
};

ListGraph random_graph(Rng& rng, std::uint32_t n) {
  ListGraph g;
  g.out.resize(n);
  for (std::uint32_t u = 0; u < n; ++u) {
    // A chain keeps most states reachable; random extra edges make alternative routes.
    if (u + 1 < n) g.out[u].push_back({u + 1, rng.uniform(0.5, 3.0)});
    for (int k = 0; k < 3; ++k)
      g.out[u].push_back({static_cast<std::uint32_t>(rng.uniform_int(0, n - 1)), rng.uniform(0.1, 5.0)});
  }
  return g;
}

// Exact costs to `goal` from every state (Dijkstra on the reversed graph).
std::vector<double> costs_to(const ListGraph& g, std::uint32_t goal) {
  std::vector<std::vector<Edge>> in(g.out.size());
  for (std::uint32_t u = 0; u < g.out.size(); ++u)
    for (const Edge& e : g.out[u]) in[e.to].push_back({u, e.cost});
  std::vector<double> d(g.out.size(), INFINITY);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> pq;
  d[goal] = 0;
  pq.push({0, goal});
  while (!pq.empty()) {
    const auto [du, u] = pq.top();
    pq.pop();
    if (du > d[u]) continue;
    for (const Edge& e : in[u])
      if (du + e.cost < d[e.to]) d[e.to] = du + e.cost, pq.push({d[e.to], e.to});
  }
  return d;
}

TEST(SearchCoreReopen, AdmissibleInconsistentHeuristicGivesOptimalCostsOnlyWithReopening) {
  Rng rng(42);
  int suboptimal_without = 0, checked = 0;
  std::uint64_t reopened = 0;
  BestFirstSearch<double, DefaultOpenList<double>, ReopenClosed> reopening;
  BestFirstSearch<double> plain;
  for (int trial = 0; trial < 300; ++trial) {
    const std::uint32_t n = 40;
    const ListGraph g = random_graph(rng, n);
    const std::uint32_t goal = n - 1;
    const std::vector<double> exact = costs_to(g, goal);
    if (!std::isfinite(exact[0])) continue;
    // Admissible (h <= exact cost to go) but inconsistent: a random fraction of the exact cost,
    // often 0 next to a state with a large h.
    TableHeuristic h;
    h.h.resize(n);
    for (std::uint32_t i = 0; i < n; ++i)
      h.h[i] = std::isfinite(exact[i]) ? (rng.uniform() < 0.5 ? exact[i] : rng.uniform(0.0, 0.3) * exact[i]) : 0.0;
    reopening.resize(n);
    plain.resize(n);
    ASSERT_EQ(reopening.run(g, h, 0, SingleGoal{goal}), SearchOutcome::Found);
    ASSERT_EQ(plain.run(g, h, 0, SingleGoal{goal}), SearchOutcome::Found);
    ++checked;
    EXPECT_NEAR(reopening.g(goal), exact[0], 1e-9) << "trial " << trial;
    EXPECT_GE(plain.g(goal), exact[0] - 1e-9);
    if (plain.g(goal) > exact[0] + 1e-9) ++suboptimal_without;
    reopened += reopening.stats().reopened;
    EXPECT_EQ(plain.stats().reopened, 0u);
    // The path's edges add up to its g.
    std::vector<std::uint32_t> path;
    reopening.path_to(goal, path);
    ASSERT_EQ(path.front(), 0u);
    double sum = 0;
    for (std::size_t i = 1; i < path.size(); ++i) {
      double best = INFINITY;
      for (const Edge& e : g.out[path[i - 1]])
        if (e.to == path[i]) best = std::min(best, e.cost);
      sum += best;
    }
    EXPECT_NEAR(sum, reopening.g(goal), 1e-9);
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(reopened, 0u);            // the heuristic did make states reopen
  EXPECT_GT(suboptimal_without, 0);  // and the test can tell the two policies apart
}

TEST(SearchCoreReopen, ConsistentHeuristicSameExpansionsAsWithoutReopening) {
  Rng rng(7);
  BestFirstSearch<double, DefaultOpenList<double>, ReopenClosed> reopening;
  BestFirstSearch<double> plain;
  for (int trial = 0; trial < 100; ++trial) {
    const std::uint32_t n = 60;
    const ListGraph g = random_graph(rng, n);
    TableHeuristic h;
    h.h = costs_to(g, n - 1);  // the perfect heuristic is consistent
    for (double& v : h.h)
      if (!std::isfinite(v)) v = 1e9;
    reopening.resize(n);
    plain.resize(n);
    std::vector<std::uint32_t> a, b;
    const auto ra = reopening.run(g, h, 0, SingleGoal{n - 1}, {}, TraceListener{&a});
    const auto rb = plain.run(g, h, 0, SingleGoal{n - 1}, {}, TraceListener{&b});
    EXPECT_EQ(ra, rb);
    EXPECT_EQ(a, b);
    EXPECT_EQ(reopening.stats().reopened, 0u);
  }
}

}  // namespace
